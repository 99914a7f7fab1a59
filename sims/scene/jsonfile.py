"""A compact JSON form of the scene model (``*.scene.json``), for scenes this repository ships.

The file is the :class:`sims.scene.model.Scene` dataclasses written field by field, leaving out
fields equal to their default; floats are rounded to 7 significant digits (what a ``.ttt``
stores, single precision); bytes (a texture's pixels) are base64 text. A mesh's texture
mapping is written without its image, which ``Scene.textures`` holds once and reading attaches
again. ``write_json`` output is deterministic (sorted keys). Reading checks every field name
and says which object and field is wrong; it never evaluates anything.
"""

from __future__ import annotations

import base64
import dataclasses
import functools
import json
import types
import typing
from pathlib import Path
from typing import Any

from sims.scene import model as M
from sims.scene.limits import LimitError, TextureBudget
from sims.scene.textures import attach_images

FORMAT = "sitegen-scene/1"


class SceneJSONError(ValueError):
    pass


def _plain(value: Any) -> Any:
    if dataclasses.is_dataclass(value):
        out = {}
        for f in dataclasses.fields(value):
            if isinstance(value, M.TextureMapping) and f.name == "image":
                continue  # held once in Scene.textures
            v = getattr(value, f.name)
            default = (
                f.default
                if f.default is not dataclasses.MISSING
                else (
                    f.default_factory()  # type: ignore[misc]
                    if f.default_factory is not dataclasses.MISSING
                    else dataclasses.MISSING
                )
            )
            if default is not dataclasses.MISSING and v == default:
                continue
            out[f.name] = _plain(v)
        return out
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, float):
        return float(f"{value:.7g}")
    if isinstance(value, bytes):
        return base64.b64encode(value).decode("ascii")
    return value


PURE = ("cuboid", "cylinder", "disc", "plane")


def derive(scene: M.Scene, source: str) -> M.Scene:
    """What the repository ships from a course scene: the objects (no embedded scripts: they
    are code, and running them is not this package's business), primitives without their
    redundant vertex lists (their ``size`` defines them), and ``source`` naming the file."""

    def slim(mesh: M.Mesh) -> M.Mesh:
        round_sphere = mesh.primitive == "sphere" and len(set(mesh.size)) == 1
        if mesh.primitive in PURE or round_sphere:
            return dataclasses.replace(mesh, vertices=(), indices=())
        return mesh

    objects = []
    for o in scene.objects:
        if o.shape is not None:
            meshes = tuple(slim(m) for m in o.shape.meshes)
            o = dataclasses.replace(o, shape=dataclasses.replace(o.shape, meshes=meshes))
        objects.append(o)
    return dataclasses.replace(scene, objects=tuple(objects), scripts=(), source=source, notes=())


def dumps(scene: M.Scene) -> str:
    data = {"format": FORMAT, "scene": _plain(scene)}
    return json.dumps(data, sort_keys=True, separators=(",", ":")) + "\n"


def write_json(scene: M.Scene, path: Path) -> None:
    path.write_text(dumps(scene), encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    """``python -m sims.scene.jsonfile SCENE.ttt OUT.scene.json [SOURCE]``: derive a scene
    description (how sims/scene/bundled/2w1a.scene.json was made)."""
    import sys

    from sims.scene.load import load_scene

    args = sys.argv[1:] if argv is None else argv
    if len(args) not in (2, 3):
        print("usage: python -m sims.scene.jsonfile SCENE OUT.scene.json [SOURCE]", file=sys.stderr)
        return 2
    scene = load_scene(args[0])
    write_json(derive(scene, args[2] if len(args) == 3 else Path(args[0]).name), Path(args[1]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())


@functools.cache
def _fields(cls: Any) -> tuple[dict[str, Any], frozenset[str]]:
    """A model class's field types and names, worked out once per class (a scene has thousands
    of values and a few dozen records: resolving the hints each time was most of a load)."""
    return typing.get_type_hints(cls, vars(M)), frozenset(f.name for f in dataclasses.fields(cls))


def _numbers(kind: type, data: list) -> tuple | None:
    """A whole vertex or index list at once when every item is of the right kind; None sends
    the list through the item-by-item path, which names the bad item."""
    seen = set(map(type, data))  # type() also refuses bool, as the slow path does
    if seen <= {kind}:
        return tuple(data)
    if kind is float and seen <= {int, float}:
        return tuple(map(float, data))
    return None


def _build(cls: Any, data: Any, where: str) -> Any:
    if not isinstance(data, dict):
        raise SceneJSONError(f"{where}: expected an object")
    hints, names = _fields(cls)
    unknown = sorted(set(data) - names)
    if unknown:
        raise SceneJSONError(f"{where}: unknown field {unknown[0]!r}")
    kwargs = {k: _value(hints[k], v, f"{where}.{k}") for k, v in data.items()}
    try:
        return cls(**kwargs)
    except TypeError as exc:
        raise SceneJSONError(f"{where}: {exc}") from exc


def _value(hint: Any, data: Any, where: str) -> Any:
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        if data is None:
            return None
        inner = [a for a in args if a is not type(None)]
        return _value(inner[0], data, where)
    if dataclasses.is_dataclass(hint):
        return _build(hint, data, where)
    if origin is tuple:
        if not isinstance(data, list):
            raise SceneJSONError(f"{where}: expected a list")
        if len(args) == 2 and args[1] is Ellipsis:
            if args[0] in (float, int):
                fast = _numbers(args[0], data)
                if fast is not None:
                    return fast
            return tuple(_value(args[0], v, f"{where}[{i}]") for i, v in enumerate(data))
        if len(args) != len(data):
            raise SceneJSONError(f"{where}: expected {len(args)} values")
        return tuple(
            _value(a, v, f"{where}[{i}]") for i, (a, v) in enumerate(zip(args, data, strict=True))
        )
    if hint is float:
        if isinstance(data, bool) or not isinstance(data, (int, float)):
            raise SceneJSONError(f"{where}: expected a number")
        return float(data)
    if hint is int and (isinstance(data, bool) or not isinstance(data, int)):
        raise SceneJSONError(f"{where}: expected an integer")
    if hint is str and not isinstance(data, str):
        raise SceneJSONError(f"{where}: expected a string")
    if hint is bytes:
        if not isinstance(data, str):
            raise SceneJSONError(f"{where}: expected base64 text")
        try:
            return base64.b64decode(data, validate=True)
        except ValueError as exc:
            raise SceneJSONError(f"{where}: not base64 ({exc})") from None
    if hint is bool and not isinstance(data, bool):
        raise SceneJSONError(f"{where}: expected true or false")
    return data


def with_textures(scene: M.Scene, where: str) -> M.Scene:
    """The scene read back with its texture objects checked (limits, pixel count) and given
    again to the meshes that wear them."""
    budget = TextureBudget()
    for t in scene.textures:
        try:
            budget.take(t.name, t.width, t.height)
        except LimitError as exc:
            raise SceneJSONError(f"{where}: {exc}") from None
        if len(t.rgba) != 4 * t.width * t.height or min(t.width, t.height) <= 0:
            raise SceneJSONError(f"{where}: texture {t.name!r}: pixels do not match its size")
    objects = list(scene.objects)
    missing = attach_images(objects, {t.id: t for t in scene.textures})
    if missing:
        raise SceneJSONError(f"{where}: {missing[0]}: its texture is not in the file")
    scene = dataclasses.replace(scene, objects=tuple(objects))
    return scene


def read_json(path: Path) -> M.Scene:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise SceneJSONError(f"{path}: not a scene description ({exc})") from exc
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise SceneJSONError(f"{path}: not a {FORMAT} file")
    scene = _build(M.Scene, data.get("scene"), str(path))
    scene = with_textures(scene, str(path))
    source = f"{path} (from {scene.source})" if scene.source else str(path)
    return dataclasses.replace(scene, source=source, format="json")
