"""Issue 33: a clip that fails publishes its error with paths relative to the project (never
this machine's layout, nor what a script tried to read), and a scene file made to exhaust
memory reaches ``sitegen build`` through a gallery clip as one warning (docs/security.md)."""

from __future__ import annotations

import struct
from pathlib import Path

from sitegen_helpers import run_cli, write_tree

from located.paths import public_paths

READER = """import sim
client = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
open("/etc/" + "sitegen-test-secret/shadow")  # the source is shown: the path is made here
"""
CONFIG = """title: t
sims:
  size: 96x64
  fps: 8
  clips:
    - {name: peek, script: scripts/peek.py, scene: cart, seconds: 1}
    - {name: bomb, script: scripts/peek.py, scene: scenes/bomb.ttt, seconds: 1}
"""


def _bomb() -> bytes:
    """A 1 KB .ttt claiming 1 GiB of zeros (a Huffman tree of one leaf takes no bits)."""
    head = b"VREP" + struct.pack("<ii", 22, 18) + bytes([1]) + struct.pack("<i", 1 << 30)
    head += struct.pack("<i", 0) + struct.pack("<H", 40100) + struct.pack("<I", 0x1001)
    return head + b"\x01\x01" + b"\x00" * 992 + bytes([0b10000000, 0]) + b"\x00" * 1000


def test_a_failed_clip_publishes_no_absolute_path(tmp_path):
    src = write_tree(
        tmp_path / "proj",
        {
            "sitegen.yml": CONFIG,
            "scripts/peek.py": READER,
            "content/index.md": "# Home\n\n::: clip peek\n\n::: clip bomb\n",
        },
    )
    (src / "scenes").mkdir()
    (src / "scenes" / "bomb.ttt").write_bytes(_bomb())
    done = run_cli("build", "--source", str(src), "--output", str(tmp_path / "site"))
    assert done.returncode == 0, done.stderr[-2000:]
    assert "Traceback" not in done.stderr
    warnings = [x for x in done.stderr.splitlines() if "sims.clips[" in x]
    assert any("sims.clips[peek]" in w and "…/shadow" in w for w in warnings), warnings
    bomb = next(w for w in warnings if "sims.clips[bomb]" in w)
    assert "scenes/bomb.ttt: error: header: claims 1073741824 bytes" in bomb
    published = b"".join(p.read_bytes() for p in (tmp_path / "site").rglob("*") if p.is_file())
    for secret in (b"/etc/sitegen-test-secret", str(tmp_path).encode(), b"/tmp/"):
        assert secret not in published, secret
    gallery = (tmp_path / "site" / "gallery" / "index.html").read_text(encoding="utf-8")
    assert "…/shadow" in gallery and "scenes/bomb.ttt: error: header" in gallery
    index = b"".join(p.read_bytes() for p in (tmp_path / "site").rglob("search*"))
    assert "…/shadow".encode() in index  # the search index has the same, rewritten text


def test_paths_are_rewritten_and_other_text_is_not():
    root = Path("/home/alice/course")
    text = (
        "/home/alice/course/scenes/a.ttt: error: x; /tmp/sitegen-lua-x1/s.lua:3: boom; "
        "'/etc/shadow'; see https://example.org/a/b, a/b, 1/2, ./local/x and ~/y"
    )
    assert public_paths(text, root) == (
        "scenes/a.ttt: error: x; …/s.lua:3: boom; '…/shadow'; see https://example.org/a/b, "
        "a/b, 1/2, ./local/x and ~/y"
    )
    assert public_paths("in /home/alice/course", root) == "in ."
