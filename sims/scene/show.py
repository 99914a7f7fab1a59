"""``sitegen scene show PATH [--json]``: what a CoppeliaSim scene file holds, as the readers see it
(and ``sitegen scene xml PATH [-o OUT]``: the same scene written as a ``.simscene.xml``).

The text form is the object tree, one object a line (name, alias, type, pose in the parent frame,
then what matters for the type: joint mode and range, shape mass and dynamics, sensor range or
resolution), the embedded scripts and the list of what was not understood. ``--json`` prints the
same as one JSON document (stable key order, rounded numbers) for tools and tests. A file that
cannot be read prints one ``file: error: object: message`` line and exits 1.

Both forms take time linear in the number of objects (the tree is walked without recursion from
the scene's child index); the JSON document is written object by object, and a scene whose
object paths would add up to more than ``MAX_PATH_CHARS`` (long names nested deep: only a file
made for it) is refused with one line instead of printing gigabytes.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Iterator

from located.verbosity import add_verbosity
from sims.scene.errors import SceneError
from sims.scene.load import load_scene
from sims.scene.model import Pose, Scene, SceneObject
from sims.scene.resolve import SceneFileError, is_bundled, open_scene
from sims.scene.rotations import euler_degrees
from sims.scene.show_mech import hand_built_report, mechanism_lines, mechanisms

MAX_PATH_CHARS = 64 * 1024 * 1024  # all objects' paths in a JSON report together
INDENT_LEVELS = 32  # deeper objects are indented as much, with their level shown


def _clean(text: str) -> str:
    """Names come from the file: keep control characters off the terminal."""
    return "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in text)


def _r(x: float, nd: int = 4) -> float:
    v = round(float(x), nd)
    return 0.0 if v == 0 else v


def _pose_text(p: Pose) -> str:
    pos = " ".join(f"{_r(v):g}" for v in p.position)
    rot = " ".join(f"{_r(v, 2):g}" for v in euler_degrees(p.quaternion))
    return f"at ({pos}) m, rot ({rot})°"


def _details(o: SceneObject) -> str:
    if o.joint:
        j = o.joint
        deg = j.kind in ("revolute", "spherical")
        unit = "°" if deg else " m"

        def val(v: float) -> str:
            return f"{_r(math.degrees(v) if deg else v, 3):g}{unit}"

        rng = "cyclic" if j.cyclic else f"[{val(j.minimum)}, {val(j.minimum + j.range)}]"
        if j.mode == "velocity" and not j.motor_enabled:
            return f"{j.kind}, free (motor off), range {rng}, position {val(j.position)}"
        text = f"{j.kind}, {j.mode}, range {rng}, position {val(j.position)}"
        if j.mode == "position":
            text += f", target {val(j.target)}, P {_r(j.p_gain):g}"
        if j.mode in ("position", "velocity"):
            text += f", max {'torque' if deg else 'force'} {_r(j.max_force):g}"
            if j.max_velocity is not None:
                text += f", max speed {val(j.max_velocity)}/s"
        if j.mode == "velocity":
            text += f", target speed {val(j.target_velocity)}/s"
        if j.mode == "spring":
            text += f", K {_r(j.spring_k):g}, C {_r(j.spring_c):g}"
        return text
    if o.shape:
        d = o.shape.dynamics
        prims = sorted({m.primitive or "mesh" for m in o.shape.meshes})
        parts = f"compound of {len(o.shape.meshes)}" if o.shape.compound else "simple"
        state = "static" if d.static else "dynamic"
        resp = "respondable" if d.respondable else "not respondable"
        text = f"{parts} ({', '.join(prims) or 'empty'}), {state}, {resp}, mass {_r(d.mass):g} kg"
        if d.friction is not None:
            text += f", friction {_r(d.friction, 3):g}"
        return text
    if o.proximity_sensor:
        s = o.proximity_sensor
        text = f"{s.volume}, range {_r(s.range):g} m"
        if s.angle:
            text += f", angle {_r(math.degrees(s.angle), 2):g}°"
        return text
    if o.vision_sensor:
        v = o.vision_sensor
        view = f"view {_r(math.degrees(v.view_angle), 2):g}°" if v.perspective else "orthographic"
        return f"{v.resolution[0]}x{v.resolution[1]}, {view}, near {_r(v.near):g} far {_r(v.far):g}"
    if o.force_sensor:
        return f"filter {o.force_sensor.filter_samples} samples"
    if o.camera:
        return f"view {_r(math.degrees(o.camera.view_angle), 2):g}°"
    if o.light:
        return f"{o.light.kind}, {'on' if o.light.enabled else 'off'}"
    if o.dummy and o.dummy.linked_to is not None:
        return f"linked to [{o.dummy.linked_to}] ({o.dummy.link_type or 'default'})"
    return ""


def text_report(scene: Scene) -> str:
    lines = [f"{_clean(scene.source)}: {scene.format} ({_clean(scene.version)})"]
    lines.append(f"{len(scene.objects)} objects, {len(scene.scripts)} scripts")
    by_handle = scene.by_handle()
    attached: dict[int, list[str]] = {}
    for s in scene.scripts:
        if s.object is not None:
            attached.setdefault(s.object, []).append(s.kind)

    lines.append("")
    shown: set[int] = set()
    for o, depth in walk_tree(scene):
        shown.add(id(o))
        label = _clean(o.name)
        if o.alias and o.alias != o.name.split("#")[0]:
            label += f" (alias {_clean(o.alias)})"
        info = [o.kind, _pose_text(o.pose)]
        detail = _details(o)
        if detail:
            info.append(detail)
        if o.handle in attached:
            info.append("script: " + ", ".join(attached[o.handle]))
        if o.model_base:
            info.append("model")
        level = f"[level {depth}] " if depth > INDENT_LEVELS else ""
        lines.append(
            f"{'  ' * min(depth, INDENT_LEVELS)}{level}{label} [{o.handle}] " + "; ".join(info)
        )
    for o in scene.objects:
        if id(o) in shown:
            continue
        why = "missing" if o.parent not in by_handle else "in a loop"
        lines.append(f"{_clean(o.name)} [{o.handle}] (parent {o.parent} {why})")
    if scene.scripts:
        lines.append("")
        lines.append("Scripts:")
        for s in scene.scripts:
            owner = by_handle.get(s.object) if s.object is not None else None
            where = f"on {_clean(owner.name)}" if owner else "scene"
            flags = [x for x, on in (("threaded", s.threaded), ("disabled", s.disabled)) if on]
            n = len(s.text.splitlines())
            lines.append(
                f"  {s.kind} ({where}){' ' + ', '.join(flags) if flags else ''}: {n} lines"
            )
    lines += mechanism_lines(scene)
    lines += texture_lines(scene)
    lines.append("")
    if scene.notes:
        lines.append("Not understood or not used:")
        lines.extend(f"  {_clean(n.where)}: {_clean(n.message)}" for n in scene.notes)
    else:
        lines.append("Everything in the file was understood.")
    return "\n".join(lines) + "\n"


def walk_tree(scene: Scene) -> Iterator[tuple[SceneObject, int]]:
    """Every object reachable from the top level, depth first in file order, with its depth;
    no recursion, each object once (objects under a missing parent or on a loop are not
    reached: the callers list them)."""
    top = scene.children(None)
    stack: list[tuple[list[SceneObject], int]] = [(top[::-1], 0)]
    seen: set[int] = set()
    while stack:
        pending, depth = stack[-1]
        if not pending:
            stack.pop()
            continue
        o = pending.pop()
        if id(o) in seen:
            continue
        seen.add(id(o))
        yield o, depth
        kids = scene.children(o.handle)
        if kids:
            stack.append((kids[::-1], depth + 1))


def _pose_json(p: Pose) -> dict:
    return {
        "position": [_r(v, 6) for v in p.position],
        "quaternion": [_r(v, 6) for v in p.quaternion],
        "euler_degrees": [_r(v, 3) for v in euler_degrees(p.quaternion)],
    }


class ReportTooLarge(ValueError):
    """The JSON report would print more than ``MAX_PATH_CHARS`` characters of object paths."""


def _paths(scene: Scene) -> dict[int, str]:
    """Every object's path (``Scene.path``), each built from its parent's: linear in the
    objects, refused beyond ``MAX_PATH_CHARS`` in all."""
    out: dict[int, str] = {}
    total = 0
    for o, _depth in walk_tree(scene):
        parent = out.get(o.parent) if o.parent is not None else ""
        path = scene.path(o) if parent is None else f"{parent}/{o.alias or o.name.split('#')[0]}"
        total += len(path)
        if total > MAX_PATH_CHARS:
            raise ReportTooLarge(
                f"the objects' paths add up to more than {MAX_PATH_CHARS} characters "
                "(long names nested deep): too much to print"
            )
        out[o.handle] = path
    return out


def json_report(scene: Scene) -> str:
    return "".join(json_pieces(scene)) + "\n"


def json_pieces(scene: Scene) -> Iterator[str]:
    """The JSON report in pieces, one object at a time (the same text as one ``json.dumps``
    of the whole document with ``indent=1``)."""
    paths = _paths(scene)
    head = _json_head(scene)
    if not scene.objects:
        yield json.dumps({**head, "objects": []}, indent=1, sort_keys=True, ensure_ascii=False)
        return
    marker = "\u0000objects"
    text = json.dumps({**head, "objects": [marker]}, indent=1, sort_keys=True, ensure_ascii=False)
    before, after = text.split(json.dumps(marker))
    yield before
    for i, o in enumerate(scene.objects):
        item = _json_object(scene, o, paths)
        piece = json.dumps(item, indent=1, sort_keys=True, ensure_ascii=False)
        yield ("" if i == 0 else ",\n  ") + piece.replace("\n", "\n  ")
    yield after


def _json_object(scene: Scene, o: SceneObject, paths: dict[int, str]) -> dict:
    item: dict = {
        "handle": o.handle,
        "name": o.name,
        "alias": o.alias,
        "path": paths.get(o.handle) or scene.path(o),
        "kind": o.kind,
        "parent": o.parent,
        "pose": _pose_json(o.pose),
        "visible": o.visible,
        "model_base": o.model_base,
    }
    if o.joint:
        item["joint"] = {k: _round(v) for k, v in vars(o.joint).items()}
    if o.shape:
        d = o.shape.dynamics
        item["shape"] = {
            "compound": o.shape.compound,
            "meshes": [
                {
                    "primitive": m.primitive,
                    "size": [_r(v, 6) for v in m.size],
                    "vertices": len(m.vertices) // 3,
                    "triangles": len(m.indices) // 3,
                    "local": _pose_json(m.local),
                    "color": [_r(v, 3) for v in m.color],
                }
                for m in o.shape.meshes
            ],
            "static": d.static,
            "respondable": d.respondable,
            "mass": _r(d.mass, 6),
            "inertia": [_r(v, 9) for v in d.inertia],
            "inertia_frame": _pose_json(d.inertia_frame),
            "friction": None if d.friction is None else _r(d.friction, 4),
            "respondable_mask": d.respondable_mask,
        }
    for key in (
        "proximity_sensor",
        "vision_sensor",
        "force_sensor",
        "camera",
        "light",
        "dummy",
    ):
        data = getattr(o, key)
        if data is not None:
            item[key] = {k: _round(v) for k, v in vars(data).items()}
    return item


def textures(scene: Scene) -> list[dict]:
    """Each texture object (no pixels) and the meshes that wear it, with the mapping understood."""
    out = []
    for t in scene.textures:
        worn = []
        for o in scene.objects:
            for m in o.shape.meshes if o.shape is not None else ():
                x = m.texture
                if x is None or x.texture != t.id:
                    continue
                worn.append(
                    {
                        "shape": o.name,
                        "mode": "fixed coordinates" if x.coordinates else x.mode,
                        "scaling": [_r(v, 4) for v in x.scaling],
                        "apply": x.apply,
                        "repeat_u": x.repeat_u,
                        "repeat_v": x.repeat_v,
                        "interpolate": x.interpolate,
                    }
                )
        out.append({"id": t.id, "name": t.name, "size": [t.width, t.height], "worn_by": worn})
    return out


def texture_lines(scene: Scene) -> list[str]:
    found = textures(scene)
    if not found:
        return []
    lines = ["", "Textures:"]
    for t in found:
        worn = []
        for w in t["worn_by"]:
            how = w["mode"]
            if how != "fixed coordinates":
                how += f" {w['scaling'][0]} x {w['scaling'][1]} m"
            flags = [f for f, key in (("repeat u", "repeat_u"), ("repeat v", "repeat_v"),
                                      ("interpolated", "interpolate")) if w[key]]  # fmt: skip
            worn.append(f"{_clean(w['shape'])} ({', '.join([how, w['apply'], *flags])})")
        on = "; ".join(worn) if worn else "not used by any shape"
        width, height = t["size"]
        lines.append(f"  {_clean(t['name'])} [{t['id']}] {width}x{height}: {on}")
    return lines


def _json_head(scene: Scene) -> dict:
    return {
        "source": scene.source,
        "format": scene.format,
        "version": scene.version,
        "gravity": [_r(v, 4) for v in scene.gravity],
        "time_step": _r(scene.time_step, 6),
        "scripts": [
            {
                "kind": s.kind,
                "object": s.object,
                "threaded": s.threaded,
                "disabled": s.disabled,
                "text": s.text,
            }
            for s in scene.scripts
        ],
        "notes": [{"where": n.where, "message": n.message} for n in scene.notes],
        "textures": textures(scene),
        **mechanisms(scene),
    }


def _round(v: object) -> object:
    if isinstance(v, float):
        return _r(v, 6)
    if isinstance(v, tuple):
        return [_round(x) for x in v]
    return v


def _open(path: str) -> Scene | str:
    """A scene file, or a bundled name as ``remote-api run`` takes it (a file that exists by
    that name wins): the shipped description, or the name of a scene built in Python."""
    import os

    if is_bundled(path) and not os.path.exists(path):
        return open_scene(path)
    return load_scene(path)


def main(argv: list[str] | None = None, prog: str = "sitegen scene") -> int:
    parser = argparse.ArgumentParser(
        prog=prog, description="Read CoppeliaSim scene files (.ttt, .simscene.xml)."
    )
    sub = parser.add_subparsers(dest="command", required=True)
    show = sub.add_parser(
        "show",
        help="print a scene's object tree and what was not understood",
        description="Print the object tree of a CoppeliaSim scene (.ttt or .simscene.xml): "
        "names, types, parents, poses, joint modes and ranges, masses, sensors, scripts, and "
        "what the reader did not understand. Loading a scene runs nothing.",
    )
    show.add_argument("path", help="the scene file, or a bundled scene name (2w1a, cart)")
    show.add_argument("--json", action="store_true", help="print JSON instead of text")
    conv = sub.add_parser(
        "xml",
        help="write a scene as CoppeliaSim's XML scene format",
        description="Read a scene (.ttt or .simscene.xml) and write it as a .simscene.xml "
        "(CoppeliaSim's simple XML format): what the readers understood, nothing else.",
    )
    conv.add_argument("path", help="the scene file")
    conv.add_argument("-o", "--output", help="file to write (default: standard output)")
    from sims.replay.cli import add_parser, export

    glb = add_parser(sub)
    for p in (show, conv, glb):  # errors always print
        add_verbosity(
            p,
            "print nothing but the scene's data and errors",
            "also say on standard error what was read and written",
        )
    args = parser.parse_args(argv)
    if args.command == "export":  # a bundled name or a file, built into a World
        return export(args, _clean)
    try:
        scene = _open(args.path)
    except (SceneError, SceneFileError) as exc:
        print(_clean(str(exc)), file=sys.stderr)
        return 1
    if isinstance(scene, str):  # a scene built by hand in Python: no file to show
        return hand_built_report(scene, args)
    if args.verbosity > 0:
        print(f"read {_clean(args.path)}: {len(scene.objects)} objects", file=sys.stderr)
    if args.command == "xml":
        from sims.scene.xml_write import write_xml

        text = write_xml(scene)
        if scene.textures and args.verbosity >= 0:  # nothing the user gave is dropped unsaid
            names = ", ".join(_clean(t.name) for t in scene.textures)
            print(
                f"{_clean(args.path)}: note: textures not written ({names}): CoppeliaSim's "
                "simple XML format has none",
                file=sys.stderr,
            )
        if args.output:
            try:
                with open(args.output, "w", encoding="utf-8", newline="\n") as fh:
                    fh.write(text)
            except OSError as exc:
                print(f"{_clean(args.output)}: file: cannot write: {exc.strerror}", file=sys.stderr)
                return 1
            if args.verbosity > 0:
                print(f"wrote {_clean(args.output)}", file=sys.stderr)
        else:
            sys.stdout.write(text)
        return 0
    if not args.json:
        sys.stdout.write(text_report(scene))
        return 0
    try:
        pieces = json_pieces(scene)
        first = next(pieces)  # the paths are checked before anything is printed
    except ReportTooLarge as exc:
        print(f"{_clean(args.path)}: error: file: {exc}", file=sys.stderr)
        return 1
    sys.stdout.write(first)
    for piece in pieces:
        sys.stdout.write(piece)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
