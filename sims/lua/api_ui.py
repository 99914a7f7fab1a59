"""User interfaces (V-REP 3.x custom UIs, ``simUI``) kept as headless records, and the scene
editing functions of the resizable floor's dialog."""

from __future__ import annotations

from typing import Any

from sims.remote_api import commands as cmd

from .api_core import REGISTRY, Context, api
from .api_simulation import remote_api_start
from .runtime import text, to_py


# -- user interfaces: kept as data, nothing is shown ----------------------------------------------
@api("getUIHandle")
def get_ui_handle(c: Context, name: Any) -> Any:
    """A V-REP 3.x custom UI saved with the scene (the floor's size dialog): kept as a headless
    record (visible, no events) so that scripts which hide or relabel it run."""
    n = text(name)
    for h, ui in c.host.uis.items():
        if ui.get("name") == n:
            return h
    return c.host.new_ui({"name": n, "property": 1})


def _ui(c: Context, h: Any) -> dict[Any, Any]:
    ui = c.host.uis.get(int(h))
    if ui is None:
        raise ValueError(f"user interface {int(h)} does not exist")
    return ui


REGISTRY["getUIProperty"] = lambda c, h: _ui(c, h).get("property", 1)
REGISTRY["setUIProperty"] = lambda c, h, v: _ui(c, h).__setitem__("property", int(v)) or 1
REGISTRY["getUIEventButton"] = lambda c, h: (_ui(c, h) and -1, [0, 0])  # nobody clicks
REGISTRY["getUISlider"] = lambda c, h, b: _ui(c, h).get(("slider", int(b)), 500)
REGISTRY["setUISlider"] = lambda c, h, b, v: _ui(c, h).__setitem__(("slider", int(b)), int(v)) or 1
REGISTRY["setUIButtonLabel"] = lambda c, h, b, up, down=None: (
    _ui(c, h).__setitem__(("label", int(b)), to_py(up)) or 1
)
REGISTRY["getUIButtonProperty"] = lambda c, h, b: _ui(c, h).get(("button", int(b)), 0)
REGISTRY["setUIButtonProperty"] = lambda c, h, b, v: (
    _ui(c, h).__setitem__(("button", int(b)), int(v)) or 1
)
REGISTRY["removeUI"] = lambda c, h: 1 if c.host.uis.pop(int(h), None) is not None else -1


REGISTRY["simUI.create"] = lambda c, xml: c.host.new_ui({"xml": text(xml)})
REGISTRY["simUI.destroy"] = lambda c, h: c.host.uis.pop(int(h), None) and None


def _ui_set(key: str):
    def fn(c: Context, h: Any, widget: Any, value: Any, *rest: Any) -> Any:
        ui = c.host.uis.get(int(h))
        if ui is None:
            return c.state.fail(f"user interface {int(h)} does not exist")
        ui[(key, int(widget))] = to_py(value)
        return None

    return fn


REGISTRY["simUI.setLabelText"] = _ui_set("label")
REGISTRY["simUI.setSliderValue"] = _ui_set("slider")
REGISTRY["simUI.setEditValue"] = _ui_set("edit")
REGISTRY["simUI.setCheckboxValue"] = _ui_set("checkbox")


REGISTRY["simRemoteApi.start"] = remote_api_start


# -- scene editing (the resizable floor's dialog) -----------------------------------------------
@api("setObjectParent")
def set_object_parent(c: Context, h: Any, parent: Any, keep_in_place: Any = True) -> Any:
    """Created objects take any parent; an object loaded with the scene keeps its place in
    the physics and its new parent is kept in the host's parent table (tree queries see it)."""
    h, parent = c.handle(h), int(parent)
    if parent != -1:
        c.check(parent)
    if h in c.host.created:
        c.host.created[h]["parent"] = parent
        return 1
    c.check(h)
    if cmd.parent(c.world, h) == parent:
        c.host.parents.pop(h, None)
    else:
        c.host.parents[h] = parent
    return 1


@api("copyPasteObjects")
def copy_paste_objects(c: Context, handles: Any, options: Any = 0) -> Any:
    """Copies are script-created objects (name, type, pose), without a physics body."""
    out = []
    for value in to_py(handles) or []:
        h = c.handle(value)
        c.check(h)
        if h in c.host.created:
            src = dict(c.host.created[h])
            base, kind = src.pop("name"), src.pop("type")
        else:
            base, kind = cmd.name(c.world, h).split("#")[0], cmd.object_type(c.world, h)
            pos, quat = cmd.frame(c.world, h)
            src = {"pos": list(pos), "quat": list(quat), "parent": -1}
        new = c.host.create(base, kind, {})
        c.host.created[new].update({k: v for k, v in src.items() if k != "name"})
        out.append(new)
    return out
