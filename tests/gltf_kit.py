"""What the replay tests share: the Khronos glTF validator (npm, tests/js) and reading a .glb.

The validator is installed by ``.ci/setup`` (``npm ci`` in tests/js); without it (or without
node) the tests that need it skip, and fail under CI.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

JS = Path(__file__).resolve().parent / "js"


def require_validator() -> str:
    node = shutil.which("node")
    missing = []
    if node is None:
        missing.append("node (apt-get install nodejs)")
    if not (JS / "node_modules" / "gltf-validator").is_dir():
        missing.append("gltf-validator (cd tests/js && npm ci)")
    if missing:
        message = "glTF validation needs " + ", ".join(missing)
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    assert node is not None
    return node


def validate(*files: Path) -> list[dict]:
    """The validator's report for each file (errors, warnings, infos, messages, info)."""
    node = require_validator()
    done = subprocess.run(
        [node, str(JS / "validate_gltf.js"), *map(str, files)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def assert_valid(path: Path) -> dict:
    """No errors and no warnings (infos allowed: named empty nodes are meant)."""
    (report,) = validate(path)
    problems = [m for m in report["messages"] if m["severity"] < 2]
    assert report["errors"] == 0 and report["warnings"] == 0, problems
    return report
