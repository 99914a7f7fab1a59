"""``sitegen scene export SCENE OUT.glb``: a scene without a run, as a glTF file.

SCENE is a bundled name (``2w1a``, ``cart``) or a scene file (``.ttt``, ``.simscene.xml``);
the file holds the scene's shapes at their saved pose, a starting camera, no animation
(sims/replay/export.py). Bad input is one line on standard error and exit 1, no traceback.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_parser(sub) -> argparse.ArgumentParser:
    export = sub.add_parser(
        "export",
        help="write a scene as a glTF 2.0 file (.glb), without a run",
        description="Build a scene (a bundled name such as 2w1a, or a .ttt / .simscene.xml "
        "file) and write its shapes at their saved pose as glTF 2.0 binary (.glb): it opens "
        "in Blender, three.js and any glTF viewer. Loading a scene runs nothing.",
    )
    export.add_argument("path", help="the scene: a bundled name or a scene file")
    export.add_argument("output", help="the .glb file to write")
    export.add_argument("--seed", type=int, default=0, help="seed of a bundled scene's layout")
    return export


def export(args: argparse.Namespace, clean) -> int:
    from sims.replay.export import scene_glb
    from sims.scene.errors import SceneError
    from sims.scene.resolve import SceneFileError

    try:
        data = scene_glb(args.path, seed=args.seed)
    except (SceneError, SceneFileError, ValueError) as exc:
        print(clean(str(exc)), file=sys.stderr)
        return 1
    try:
        Path(args.output).write_bytes(data)
    except OSError as exc:
        print(f"{clean(args.output)}: file: cannot write: {exc.strerror}", file=sys.stderr)
        return 1
    if args.verbosity > 0:
        print(f"wrote {clean(args.output)} ({len(data)} bytes)", file=sys.stderr)
    return 0
