"""The GitHub Actions workflows work: their commands run here, and the GitHub-only parts that
matter are set up right.

Checking a workflow's text (this step contains that string) passes while the commands fail,
so this runs the ``run:`` steps of ``ci.yml`` and ``pages.yml`` in order, with bash, in a
temporary copy of the repository (the files git tracks or would track) beside a ``shared``
folder, as GitHub would. Steps that only GitHub can run (``uses:`` actions: checkout,
setup-python, cache, Pages upload and deploy) are skipped; the few commands that would change
this machine or take many minutes run in a local form, each named in :data:`LOCAL` with why.
What only GitHub checks is tested as structure: the Pages deploy permissions and job, and the
clip cache key.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
WORKFLOWS = REPO / ".github" / "workflows"
CI = WORKFLOWS / "ci.yml"
PAGES = WORKFLOWS / "pages.yml"
SHARED = REPO.parent / "shared"

# Command fragment -> (the local form, why). Anything else in a run: step runs unchanged.
LOCAL = {
    "bash .ci/setup": (
        "bash -n .ci/setup",
        "installing would re-point this machine's editable install at the copy: syntax only",
    ),
    "python3 -m pytest -q": (
        "python3 -m pytest -q --collect-only -p no:cacheprovider",
        "the whole suite is what runs this test: every test module must import and collect",
    ),
    ". .venv/bin/activate": (
        ":",
        "setup only had its syntax checked, so there is no .venv: this interpreter's is used",
    ),
    "python3 -m pip install -q -e .": (
        "python3 -m pip install -q --dry-run --no-deps -e .",
        "the package must build and resolve; installing it would re-point this machine's install",
    ),
}
# Lines dropped from run: steps: system packages need root and GitHub's runner.
DROPPED = re.compile(r"^\s*sudo\s")
# ${{ expression }} -> value here (GitHub fills these in).
EXPRESSIONS = {
    "vars.SHARED_REPO": "local/shared" if SHARED.is_dir() else "",
    "steps.pages.outputs.base_url": "",
}


def load(path: Path) -> dict:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert isinstance(data, dict), f"{path.name}: not a mapping"
    if True in data:  # YAML 1.1 reads the key `on` as True
        data["on"] = data.pop(True)
    return data


def steps(wf: dict, job: str | None = None) -> list[dict]:
    jobs = wf["jobs"] if job is None else {job: wf["jobs"][job]}
    return [s for j in jobs.values() for s in j.get("steps", [])]


def uses(step: dict) -> str:
    return str(step.get("uses", "")).split("@")[0]


def _expand(text: str) -> str:
    def value(m: re.Match) -> str:
        expr = m.group(1).strip()
        if expr not in EXPRESSIONS:
            raise AssertionError(f"no local value for ${{{{ {expr} }}}}: add it to EXPRESSIONS")
        return EXPRESSIONS[expr]

    return re.sub(r"\$\{\{(.*?)\}\}", value, text)


def local_script(run: str) -> str:
    lines = [line for line in run.splitlines() if not DROPPED.match(line)]
    script = "\n".join(lines)
    for fragment, (local, _why) in LOCAL.items():
        script = script.replace(fragment, local)
    return _expand(script)


def _shorten_clips(copy: Path) -> None:
    """The Pages build renders every clip of sitegen.yml: minutes of CPU. Here each clip is
    one simulated second at a small size -- the steps still build, strictly, and check the
    whole site; full-length rendering is tested in tests/test_sims_*."""
    config = copy / "sitegen.yml"
    data = yaml.safe_load(config.read_text(encoding="utf-8"))
    sims = data.get("sims") or {}
    sims["size"] = "160x120"
    sims["fps"] = 10
    for clip in sims.get("clips") or []:
        clip["seconds"] = float(clip.get("after") or 0) + 1
        clip["speed"] = 1
    config.write_text(yaml.safe_dump(data, allow_unicode=True), encoding="utf-8")


# Outside a git checkout (an unpacked archive), these are not copied: what .gitignore names.
UNTRACKED = {".git", "site", "build", "dist", ".sitegen-cache", "test-artifacts", "__pycache__"}


def _repo_files() -> list[str]:
    """The files a fresh clone would have (plus new ones git would add)."""
    if (REPO / ".git").exists():
        listed = subprocess.run(
            ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            cwd=REPO,
            capture_output=True,
            check=True,
        ).stdout.split(b"\0")
        return [os.fsdecode(name) for name in listed if name]
    return [
        path.relative_to(REPO).as_posix()
        for path in REPO.rglob("*")
        if path.is_file()
        and not UNTRACKED & set(path.relative_to(REPO).parts)
        and not any(part.endswith(".egg-info") for part in path.parts)
    ]


def _copy_repo(dest: Path) -> Path:
    copy = dest / "repo"
    for name in _repo_files():
        src = REPO / name
        if src.is_file():
            target = copy / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, target)
    return copy


def _check_out_shared(copy: Path) -> None:
    """What the workflows' checkout of the shared data leaves in the workspace (a link here;
    the workflow's own step then moves it beside the repository)."""
    if SHARED.is_dir() and not (copy / "shared").is_symlink():
        (copy / "shared").symlink_to(SHARED, target_is_directory=True)


def _tools(folder: Path) -> str:
    """A PATH whose ``python3``/``python`` is this interpreter and whose ``ruff`` is this
    interpreter's, whatever is first on the caller's PATH (a venv run without activating it):
    the steps' ``. .venv/bin/activate`` is a no-op here (:data:`LOCAL`)."""
    folder.mkdir(parents=True, exist_ok=True)
    wrappers = {"python3": f'exec "{sys.executable}" "$@"'}
    wrappers["python"] = wrappers["python3"]
    if importlib.util.find_spec("ruff") is not None:
        wrappers["ruff"] = f'exec "{sys.executable}" -m ruff "$@"'
    for name, line in wrappers.items():
        (folder / name).write_text(f"#!/bin/sh\n{line}\n", encoding="utf-8")
        (folder / name).chmod(0o755)
    return os.pathsep.join([str(folder), str(Path(sys.executable).parent), os.environ["PATH"]])


def run_steps(wf_path: Path, copy: Path) -> list[str]:
    """Run every run: step of the workflow in the copy; return the names of those skipped."""
    wf = load(wf_path)
    skipped = []
    _check_out_shared(copy)
    env = {**os.environ, **{k: str(v) for k, v in (wf.get("env") or {}).items()}}
    env["PATH"] = _tools(copy.parent / "tools")
    for job_name, job in wf["jobs"].items():
        job_env = {**env, **{k: str(v) for k, v in (job.get("env") or {}).items()}}
        for step in job.get("steps", []):
            name = step.get("name") or step.get("uses") or "?"
            if "run" not in step:
                skipped.append(f"{job_name}: {name}")
                continue
            step_env = {k: _expand(str(v)) for k, v in (step.get("env") or {}).items()}
            proc = subprocess.run(
                ["bash", "-eo", "pipefail", "-c", local_script(str(step["run"]))],
                cwd=copy,
                env={**job_env, **step_env},
                capture_output=True,
                text=True,
                timeout=600,
            )
            assert proc.returncode == 0, (
                f"{wf_path.name}: job {job_name}, step {name!r} failed ({proc.returncode}):\n"
                f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
            )
    return skipped


@pytest.fixture(scope="module")
def copy(tmp_path_factory) -> Path:
    return _copy_repo(tmp_path_factory.mktemp("workflows"))


def test_ci_steps_run(copy: Path) -> None:
    skipped = run_steps(CI, copy)
    assert "test: Check out the repository" in skipped
    if SHARED.is_dir():
        assert (copy.parent / "shared" / "data").is_dir(), "shared data is not beside the repo"


def test_pages_steps_build_and_check_the_site(copy: Path) -> None:
    _shorten_clips(copy)
    run_steps(PAGES, copy)
    index = copy / "site" / "index.html"
    assert index.is_file(), "the build step wrote no site/index.html"
    assert "<html" in index.read_text(encoding="utf-8").lower()


def test_local_forms_are_used() -> None:
    """Every local form stands for a command a workflow really runs (no stale entries)."""
    text = CI.read_text(encoding="utf-8") + PAGES.read_text(encoding="utf-8")
    for fragment in LOCAL:
        assert fragment in text, f"LOCAL names {fragment!r}, which no workflow runs any more"


def readme_commands() -> list[str]:
    """The README's two commands: the first lines of its first code block."""
    text = (REPO / "README.md").read_text(encoding="utf-8")
    block = text.split("```", 2)[1]
    return [line for line in block.splitlines()[1:] if line.strip()]


def test_readme_ci_and_ci_run_share_the_test_command() -> None:
    build, tests = readme_commands()
    assert "venv" in build and "pip install ." in build and "sitegen build" in build
    assert "-e" not in build.split(), "the README installs as a user does, not editable"
    run_lines = (REPO / ".ci/run").read_text(encoding="utf-8").splitlines()
    assert any(line.startswith(tests) for line in run_lines), ".ci/run does not run it"
    ci_runs = [str(s["run"]).strip() for s in steps(load(CI)) if "run" in s]
    assert tests in ci_runs, "ci.yml's test step is not the README's test command"


# --- what only GitHub runs: structure ----------------------------------------------------


def test_ci_runs_on_every_push_and_pull_request_and_checks_style() -> None:
    ci = load(CI)
    assert {"push", "pull_request"} <= set(ci["on"])
    commands = [str(s["run"]) for s in steps(ci) if "run" in s]
    assert any("ruff check ." in r for r in commands)
    assert any("ruff format --check ." in r for r in commands)


def test_pages_can_deploy() -> None:
    """Without pages: write and id-token: write, deploy-pages fails on GitHub only."""
    pages = load(PAGES)
    assert pages["permissions"] == {"contents": "read", "pages": "write", "id-token": "write"}
    assert "pull_request" not in pages["on"], "pull requests must not deploy"
    build = pages["jobs"]["build"]
    (upload,) = [s for s in build["steps"] if uses(s) == "actions/upload-pages-artifact"]
    assert str(upload["with"]["path"]).rstrip("/") == "site"
    deploy = pages["jobs"]["deploy"]
    assert "build" in ([deploy["needs"]] if isinstance(deploy["needs"], str) else deploy["needs"])
    assert deploy["environment"]["name"] == "github-pages"
    (step,) = [s for s in deploy["steps"] if uses(s) == "actions/deploy-pages"]
    assert f"steps.{step['id']}.outputs.page_url" in str(deploy["environment"]["url"])


def test_clip_cache_key_follows_what_clips_are_made_of() -> None:
    """The key must change when the simulation code, the config or the scenes change (else a
    stale clip is deployed), and a partial hit must be allowed (the cache is per clip)."""
    pages = load(PAGES)
    build_steps = pages["jobs"]["build"]["steps"]
    (cache,) = [s for s in build_steps if uses(s) == "actions/cache"]
    assert str(cache["with"]["path"]).strip().rstrip("/") == ".sitegen-cache"
    key = str(cache["with"]["key"])
    hashed = re.findall(r"'([^']+)'", key.partition("hashFiles(")[2])
    for pattern in ("sims/**/*.py", "sitegen.yml", "data/**"):
        assert pattern in hashed, f"clip cache key ignores {pattern}"
    assert any(p.startswith("examples/") for p in hashed) or not any(
        "examples/" in str(c.get("script", "")) for c in _clips()
    ), "clips run scripts from examples/, which the cache key does not hash"
    prefix = key.split("${{")[0]
    assert prefix in str(cache["with"]["restore-keys"]).split()
    build_at = next(i for i, s in enumerate(build_steps) if "sitegen build" in str(s.get("run")))
    assert build_steps.index(cache) < build_at


def _clips() -> list[dict]:
    data = yaml.safe_load((REPO / "sitegen.yml").read_text(encoding="utf-8"))
    return list(((data or {}).get("sims") or {}).get("clips") or [])
