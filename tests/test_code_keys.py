"""located.code_keys: a cache's key covers the code that runs, found from the code itself."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from sitegen_helpers import REPO

from located.code_keys import closure, code_key, third_party


def modules(*roots: str) -> set[str]:
    return {name for name, _path in closure(*roots)}


def test_markdown_key_covers_what_renders_and_nothing_else():
    found = modules("sitegen.markdown_render")
    assert {"sitegen.slugs", "sitegen.highlight_cache", "sitegen.md_nested_fences"} <= found
    assert not {m for m in found if m.startswith("sims")}
    assert {"markdown", "pygments"} <= {top for top, _v in third_party("sitegen.markdown_render")}


def test_clip_key_follows_plugin_tables_and_package_listings():
    found = modules("sims.clip_worker")
    # named in sims.sources.SOURCE_KINDS as "module:function" strings
    assert "sims.remote_api.script_clips" in found
    # reached from the script runner: a scene's Lua runs in script clips
    assert "sims.lua.host" in found
    # sims.scenarios lists its own modules (pkgutil.iter_modules): every scenario runs
    scenario_files = {p.stem for p in (REPO / "sims" / "scenarios").glob("*.py")} - {"__init__"}
    assert {f"sims.scenarios.{s}" for s in scenario_files} <= found


def _key_in(code: Path, memo: Path, root: str) -> str:
    env = {**os.environ, "PYTHONPATH": str(code), "SITEGEN_CODE_MEMO": str(memo)}
    run = subprocess.run(
        [
            sys.executable,
            "-c",
            f"from located.code_keys import code_key; print(code_key({root!r}))",
        ],
        capture_output=True,
        text=True,
        env=env,
        cwd=code,
        check=True,
    )
    return run.stdout.strip()


def test_an_edit_changes_the_keys_that_cover_it_only(tmp_path):
    """A copy of the packages: editing a shim script (data of sims.remote_api, run by the
    remote API scripts) changes the clip key and leaves the Markdown key alone; editing the
    heading-id code changes the Markdown key. The memo of imports is reused between runs."""
    code = tmp_path / "code"
    for name in ("located", "sims", "sitegen"):
        shutil.copytree(REPO / name, code / name, ignore=shutil.ignore_patterns("__pycache__"))
    memo = tmp_path / "memo.json"
    before = {r: _key_in(code, memo, r) for r in ("sims.clip_worker", "sitegen.markdown_render")}
    assert memo.is_file()
    shim = code / "sims" / "remote_api" / "shim" / "sim.py"
    shim.write_text(shim.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
    assert _key_in(code, memo, "sims.clip_worker") != before["sims.clip_worker"]
    assert _key_in(code, memo, "sitegen.markdown_render") == before["sitegen.markdown_render"]
    slugs = code / "sitegen" / "slugs.py"
    slugs.write_text(slugs.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
    assert _key_in(code, memo, "sitegen.markdown_render") != before["sitegen.markdown_render"]


def test_key_is_the_same_for_the_same_code():
    assert code_key("sitegen.markdown_render") == code_key("sitegen.markdown_render")
    assert code_key("sitegen.markdown_render") != code_key("sims.clip_worker")
