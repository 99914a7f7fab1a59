"""The GitHub Actions workflows: CI runs the README's test command; Pages builds strictly and deploys.

The workflows only run on GitHub, so these tests read them as data and check what matters:
triggers, the commands, the clip cache, the Pages permissions and jobs, and pinned actions.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
WORKFLOWS = REPO / ".github" / "workflows"
CI = WORKFLOWS / "ci.yml"
PAGES = WORKFLOWS / "pages.yml"

# The block README.md opens with (used only while README.md has no fenced block yet).
EXPECTED_README_BLOCK = [
    "python3 -m pip install -e . && sitegen build",
    "bash .ci/setup && python3 -m pytest -q",
]
README_HEAD_LINES = 40

# Oldest major version of each action we accept (older ones are deprecated or shut down).
MIN_MAJOR = {
    "actions/checkout": 4,
    "actions/setup-python": 5,
    "actions/cache": 4,
    "actions/upload-artifact": 4,
    "actions/configure-pages": 5,
    "actions/upload-pages-artifact": 3,
    "actions/deploy-pages": 4,
}
PINNED = re.compile(
    r"^(?P<action>[\w.-]+/[\w./-]+)@(?P<ref>v(?P<major>\d+)(\.\d+){0,2}|[0-9a-f]{40})$"
)


def load(path: Path) -> dict:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert isinstance(data, dict), f"{path.name}: not a mapping"
    # YAML 1.1 (PyYAML) reads the key `on` as the boolean True.
    if True in data:
        data["on"] = data.pop(True)
    return data


def triggers(wf: dict) -> dict:
    on = wf["on"]
    if isinstance(on, str):
        return {on: None}
    if isinstance(on, list):
        return dict.fromkeys(on)
    return dict(on)


def steps(wf: dict, job: str | None = None) -> list[dict]:
    jobs = wf["jobs"] if job is None else {job: wf["jobs"][job]}
    return [s for j in jobs.values() for s in j.get("steps", [])]


def uses(step: dict) -> str:
    return str(step.get("uses", "")).split("@")[0]


def step_using(wf: dict, action: str, job: str | None = None) -> list[dict]:
    return [s for s in steps(wf, job) if uses(s) == action]


def runs(wf: dict, job: str | None = None) -> list[str]:
    return [str(s["run"]) for s in steps(wf, job) if "run" in s]


def run_index(wf: dict, job: str, needle: str) -> int:
    for i, s in enumerate(steps(wf, job)):
        if needle in str(s.get("run", "")):
            return i
    raise AssertionError(f"no run step in job {job!r} contains {needle!r}")


def readme_test_command() -> str:
    """The line with `pytest` in the fenced block README.md opens with."""
    head = (REPO / "README.md").read_text(encoding="utf-8").splitlines()[:README_HEAD_LINES]
    fences = [i for i, line in enumerate(head) if line.lstrip().startswith("```")]
    if len(fences) < 2:
        warnings.warn(
            "README.md has no fenced block in its first lines yet; using the expected one",
            stacklevel=2,
        )
        block = EXPECTED_README_BLOCK
    else:
        block = [line.strip() for line in head[fences[0] + 1 : fences[1]] if line.strip()]
    build = [line for line in block if line.endswith("sitegen build")]
    test = [line for line in block if "pytest" in line]
    assert build, f"README.md's first block has no command ending in 'sitegen build': {block}"
    assert len(test) == 1, f"README.md's first block should have one pytest command: {block}"
    return test[0].removeprefix("$ ").strip()


@pytest.fixture(scope="module")
def ci() -> dict:
    return load(CI)


@pytest.fixture(scope="module")
def pages() -> dict:
    return load(PAGES)


# --- CI -------------------------------------------------------------------------------------


def test_ci_runs_on_every_push_and_pull_request(ci: dict) -> None:
    on = triggers(ci)
    assert "push" in on and "pull_request" in on
    for event in ("push", "pull_request"):
        filters = on[event] or {}
        assert not set(filters) & {"branches", "paths", "tags"}, (
            f"CI {event} is filtered: {filters}"
        )


def test_ci_runs_the_readme_test_command(ci: dict) -> None:
    command = readme_test_command()
    assert any(command in r for r in runs(ci)), f"no run step of ci.yml runs {command!r}"
    env = {**ci.get("env", {}), **next(iter(ci["jobs"].values())).get("env", {})}
    step = next(s for s in steps(ci) if command in str(s.get("run", "")))
    env.update(step.get("env", {}))
    assert str(env.get("CI", "")).lower() == "true", (
        "CI=true makes the browser/shared tests fail, not skip"
    )


def test_ci_script_runs_the_readme_test_command() -> None:
    command = readme_test_command()
    assert command in (REPO / ".ci" / "run").read_text(encoding="utf-8")


def test_ci_lints_and_keeps_screenshots(ci: dict) -> None:
    (job,) = ci["jobs"]
    assert any(r.strip() == "ruff check ." for r in runs(ci))
    assert run_index(ci, job, "pytest") < run_index(ci, job, "ruff check .")
    (upload,) = step_using(ci, "actions/upload-artifact")
    assert "always()" in str(upload.get("if", "")), "screenshots matter most when tests fail"
    assert str(upload["with"]["path"]).rstrip("/") == "test-artifacts"


def test_ci_sets_up_python_with_pip_cache(ci: dict) -> None:
    (setup,) = step_using(ci, "actions/setup-python")
    assert str(setup["with"]["python-version"]) == "3.11"
    assert setup["with"].get("cache") == "pip"


def _checks_out_shared_beside_repo(wf: dict) -> None:
    shared = [s for s in step_using(wf, "actions/checkout") if "repository" in s.get("with", {})]
    assert shared, "no checkout of the shared data repository"
    (step,) = shared
    assert "vars.SHARED_REPO" in str(step["with"]["repository"])
    assert "SHARED_REPO" in str(step.get("if", "")), "skip the checkout when SHARED_REPO is unset"
    inside = str(step["with"]["path"]).strip("/")
    assert not inside.startswith(".."), "actions/checkout cannot write outside the workspace"
    assert any(
        re.search(rf"(mv|ln -s\w*) +{re.escape(inside)}/? +\.\./shared", r) for r in runs(wf)
    ), "shared/ must end up at ../shared"
    assert any("::warning" in r or "::notice" in r or "::error" in r for r in runs(wf)), (
        "say clearly when SHARED_REPO is unset"
    )


def test_ci_puts_the_shared_data_beside_the_repo(ci: dict) -> None:
    _checks_out_shared_beside_repo(ci)


# --- Pages ----------------------------------------------------------------------------------


def test_pages_runs_on_push_to_main_and_by_hand(pages: dict) -> None:
    on = triggers(pages)
    assert "workflow_dispatch" in on
    assert "main" in (on["push"] or {}).get("branches", [])
    assert "pull_request" not in on, "pull requests must not deploy"


def test_pages_permissions_and_concurrency(pages: dict) -> None:
    assert pages["permissions"] == {"contents": "read", "pages": "write", "id-token": "write"}
    assert pages["concurrency"]["group"] == "pages"
    assert pages["concurrency"]["cancel-in-progress"] is False


def test_pages_builds_strictly_then_checks_then_uploads_site(pages: dict) -> None:
    build = run_index(pages, "build", "sitegen build")
    assert "--strict" in steps(pages, "build")[build]["run"]
    check = run_index(pages, "build", "sitegen check site")
    (upload,) = step_using(pages, "actions/upload-pages-artifact", "build")
    assert str(upload["with"]["path"]).rstrip("/") == "site"
    assert build < check < steps(pages, "build").index(upload)
    assert step_using(pages, "actions/configure-pages", "build")
    installs = [r for r in runs(pages, "build") if "pip install" in r]
    assert installs and all("-e ." in r for r in installs)


def test_pages_caches_clips_by_content_hash(pages: dict) -> None:
    (cache,) = step_using(pages, "actions/cache", "build")
    opts = cache["with"]
    assert str(opts["path"]).strip().rstrip("/") == ".sitegen-cache"
    key = str(opts["key"])
    assert "hashFiles(" in key
    for pattern in ("sims/**/*.py", "sitegen.yml", "data/**"):
        assert pattern in key, f"clip cache key ignores {pattern}"
    prefix = key.split("${{")[0]
    assert prefix and prefix in str(opts["restore-keys"]).split(), (
        "restore-keys: a partial hit is safe"
    )
    assert steps(pages, "build").index(cache) < run_index(pages, "build", "sitegen build")


def test_pages_deploy_job(pages: dict) -> None:
    deploy = pages["jobs"]["deploy"]
    needs = deploy["needs"]
    assert "build" in ([needs] if isinstance(needs, str) else needs)
    assert deploy["environment"]["name"] == "github-pages"
    (step,) = step_using(pages, "actions/deploy-pages", "deploy")
    assert f"steps.{step['id']}.outputs.page_url" in str(deploy["environment"]["url"])


def test_pages_has_shared_data_when_the_config_needs_it(pages: dict) -> None:
    if "../shared" not in (REPO / "sitegen.yml").read_text(encoding="utf-8"):
        pytest.skip("sitegen.yml does not read ../shared")
    _checks_out_shared_beside_repo(pages)


# --- Both -----------------------------------------------------------------------------------


@pytest.mark.parametrize("path", [CI, PAGES], ids=lambda p: p.name)
def test_every_action_is_pinned(path: Path) -> None:
    wf = load(path)
    blocks = steps(wf) + list(wf["jobs"].values())
    used = [str(b["uses"]) for b in blocks if "uses" in b]
    assert used
    for ref in used:
        m = PINNED.match(ref)
        assert m, f"{path.name}: {ref} is not pinned to a version tag or commit"
        minimum = MIN_MAJOR.get(m["action"])
        if minimum and m["major"]:
            assert int(m["major"]) >= minimum, f"{path.name}: {ref} is older than v{minimum}"
