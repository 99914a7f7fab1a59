"""User interfaces kept as headless records (CoppeliaSim's headless mode has them too): V-REP
3.x custom UIs (``sim.getUIHandle``...), ``simUI`` (4.x Qt UIs from XML) and dialogs. Values
are readable and settable (a slider's value, an edit box's text, a checkbox); nobody clicks, so
no button event ever comes; dialogs are answered at once ("ok") with their text on the status
bar. Drawing objects are kept as data (their items) for the clip."""

from __future__ import annotations

import re
from typing import Any

from .context import Caller, SimError
from .values import integer, numbers, text

_ID = re.compile(r"""<(\w+)\b([^>]*?)\bid\s*=\s*["'](\d+)["']([^>]*)>""")
_ATTR = re.compile(r"""(\w[\w-]*)\s*=\s*["']([^"']*)["']""")


def _ui(c: Caller, h: Any) -> dict[Any, Any]:
    ui = c.store.uis.get(integer(h, 1))
    if ui is None:
        raise SimError(f"user interface {h} does not exist")
    return ui


def _new_ui(c: Caller, data: dict[Any, Any]) -> int:
    h = c.store.new_handle("ui", 1)
    c.store.uis[h] = dict(data)
    return h


# -- V-REP 3.x custom UIs ------------------------------------------------------------------------
def get_ui_handle(c: Caller, name: Any) -> int:
    n = text(name)
    for h, ui in c.store.uis.items():
        if ui.get("name") == n:
            return h
    return _new_ui(c, {"name": n, "property": 1})


def get_ui_property(c: Caller, h: Any) -> int:
    return int(_ui(c, h).get("property", 1))


def set_ui_property(c: Caller, h: Any, value: Any) -> int:
    _ui(c, h)["property"] = integer(value, 2)
    return c.done


def get_ui_event_button(c: Caller, h: Any) -> tuple[int, list[int]]:
    _ui(c, h)
    return -1, [0, 0]  # nobody clicks


def get_ui_slider(c: Caller, h: Any, button: Any) -> int:
    return int(_ui(c, h).get(("slider", integer(button, 2)), 500))


def set_ui_slider(c: Caller, h: Any, button: Any, value: Any) -> int:
    _ui(c, h)[("slider", integer(button, 2))] = integer(value, 3)
    return c.done


def set_ui_button_label(c: Caller, h: Any, button: Any, up: Any, down: Any = None) -> int:
    _ui(c, h)[("label", integer(button, 2))] = up
    return c.done


def get_ui_button_label(c: Caller, h: Any, button: Any) -> Any:
    return _ui(c, h).get(("label", integer(button, 2)), "")


def get_ui_button_property(c: Caller, h: Any, button: Any) -> int:
    return int(_ui(c, h).get(("button", integer(button, 2)), 0))


def set_ui_button_property(c: Caller, h: Any, button: Any, value: Any) -> int:
    _ui(c, h)[("button", integer(button, 2))] = integer(value, 3)
    return c.done


def remove_ui(c: Caller, h: Any) -> int:
    return 1 if c.store.uis.pop(integer(h, 1), None) is not None else -1


# -- simUI (4.x) ---------------------------------------------------------------------------------
def simui_create(c: Caller, xml: Any) -> int:
    """The UI's widgets with an ``id`` start with the values their XML gives."""
    x = text(xml)
    data: dict[Any, Any] = {"xml": x}
    for tag, before, wid, after in _ID.findall(x):
        attrs = dict(_ATTR.findall(before + after))
        key = int(wid)
        if tag == "hslider" or tag == "vslider" or tag == "slider":
            data[("slider", key)] = int(float(attrs.get("value", attrs.get("minimum", 0))))
        elif tag == "edit" or tag == "spinbox":
            data[("edit", key)] = attrs.get("value", "")
        elif tag == "checkbox" or tag == "radiobutton":
            data[("checkbox", key)] = 2 if attrs.get("checked") == "true" else 0
        elif tag == "label":
            data[("label", key)] = attrs.get("text", "")
        elif tag == "button":
            data[("button", key)] = attrs.get("text", "")
    return _new_ui(c, data)


def simui_destroy(c: Caller, h: Any) -> None:
    c.store.uis.pop(integer(h, 1), None)


def _simui_set(key: str):
    def fn(c: Caller, h: Any, widget: Any, value: Any, *rest: Any) -> None:
        _ui(c, h)[(key, integer(widget, 2))] = value

    return fn


def _simui_get(key: str, default: Any):
    def fn(c: Caller, h: Any, widget: Any) -> Any:
        return _ui(c, h).get((key, integer(widget, 2)), default)

    return fn


SIMUI = {
    "simUI.create": simui_create,
    "simUI.destroy": simui_destroy,
    "simUI.setLabelText": _simui_set("label"),
    "simUI.getLabelText": _simui_get("label", ""),
    "simUI.setSliderValue": _simui_set("slider"),
    "simUI.getSliderValue": _simui_get("slider", 0),
    "simUI.setEditValue": _simui_set("edit"),
    "simUI.getEditValue": _simui_get("edit", ""),
    "simUI.setCheckboxValue": _simui_set("checkbox"),
    "simUI.getCheckboxValue": _simui_get("checkbox", 0),
    "simUI.setButtonText": _simui_set("button"),
    "simUI.setSpinboxValue": _simui_set("edit"),
    "simUI.getSpinboxValue": _simui_get("edit", 0),
    "simUI.setEnabled": _simui_set("enabled"),
    "simUI.setTitle": lambda c, h, title: _ui(c, h).__setitem__("title", title),
    "simUI.setPosition": lambda c, h, x, y, *r: _ui(c, h).__setitem__("position", (x, y)),
    "simUI.getPosition": lambda c, h: _ui(c, h).get("position", (0, 0)),
    "simUI.show": lambda c, h: _ui(c, h).__setitem__("visible", True),
    "simUI.hide": lambda c, h: _ui(c, h).__setitem__("visible", False),
    "simUI.isVisible": lambda c, h: bool(_ui(c, h).get("visible", True)),
    "simUI.setImageData": _simui_set("image"),
    "simUI.setPlotVisible": lambda c, h, *r: None,
    "simUI.clearCurve": lambda c, h, *r: None,
    "simUI.addCurve": lambda c, h, *r: None,
    "simUI.addCurveTimePoints": lambda c, h, *r: None,
    "simUI.addCurveXYPoints": lambda c, h, *r: None,
    "simUI.rebuildPlot": lambda c, h, *r: None,
}


# -- dialogs -------------------------------------------------------------------------------------
def display_dialog(c: Caller, title: Any, main: Any, style: Any, modal: Any, *rest: Any) -> int:
    c.status(f"dialog: {text(title)}: {text(main, 2)}")
    return _new_ui(c, {"dialog": text(main, 2), "input": text(rest[0]) if rest and rest[0] else ""})


def end_dialog(c: Caller, h: Any) -> int:
    c.store.uis.pop(integer(h, 1), None)
    return c.done


def get_dialog_result(c: Caller, h: Any) -> int:
    return 1  # sim.dlgret_ok: a headless dialog is answered at once


def get_dialog_input(c: Caller, h: Any) -> str:
    ui = c.store.uis.get(integer(h, 1)) or {}
    return str(ui.get("input", ""))


def msg_box(c: Caller, kind: Any, buttons: Any, title: Any, message: Any) -> int:
    c.status(f"message box: {text(title, 3)}: {text(message, 4)}")
    return 16  # sim.msgbox_return_ok


def aux_func(c: Caller, what: Any, *args: Any) -> Any:
    return None  # its helpers open windows; nothing to do headless


# -- drawing objects (kept as data) ----------------------------------------------------------------
def add_drawing_object(c: Caller, kind: Any, size: Any, *rest: Any) -> int:
    """A drawing object's items are kept (``Store.drawings``) with the object it is attached
    to, its size and colour; a clip can draw them."""
    args = list(rest) + [None] * 8
    h = c.store.new_handle("drawing", 5_000_000)
    c.store.drawings[h] = {
        "type": integer(kind, 1),
        "size": float(size or 0),
        "duplicate_tolerance": args[0],
        "parent": args[1] if isinstance(args[1], int) else -1,
        "max_items": int(args[2] or 0),
        "color": numbers(args[3])[:3],
        "items": [],
    }
    return h


def add_drawing_object_item(c: Caller, h: Any, data: Any) -> int:
    hh = integer(h, 1)
    d = c.store.drawings.get(hh)
    if d is None:
        if hh == -1:
            return 0
        raise SimError(f"drawing object {hh} does not exist")
    if data is None:
        d["items"].clear()
        return c.done
    d["items"].append(numbers(data))
    if d["max_items"] > 0 and len(d["items"]) > d["max_items"]:
        del d["items"][0]
    return c.done


def add_drawing_object_items(c: Caller, h: Any, data: Any) -> int:
    d = c.store.drawings.get(integer(h, 1))
    if d is None:
        raise SimError(f"drawing object {h} does not exist")
    vals = numbers(data)
    per = {0: 3, 1: 6, 2: 9}.get(d["type"] & 0xFF, 3)
    for i in range(0, len(vals) - per + 1, per):
        add_drawing_object_item(c, h, vals[i : i + per])
    return c.done


def remove_drawing_object(c: Caller, h: Any) -> int:
    hh = integer(h, 1)
    if hh == -2:  # sim.handle_all
        c.store.drawings.clear()
    else:
        c.store.drawings.pop(hh, None)
    return c.done


def add_banner(c: Caller, label: Any, size: Any, opts: Any, *rest: Any) -> int:
    c.status(f"banner: {text(label)}")
    return c.store.new_handle("banner", 1)


def remove_banner(c: Caller, h: Any) -> int:
    return 1
