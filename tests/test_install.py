"""sitegen as a new user installs it: the wheel (not an editable checkout) in a fresh virtual
environment makes a ``sitegen new`` site that builds strictly and checks clean, and the
starter's own workflow steps pass from that install.

The wheel is installed with ``--no-deps`` into a new virtual environment that sees this
interpreter's dependencies (a folder of links to them, none of sitegen's own files), so CI
downloads nothing; the environment then holds no trace of this checkout, which is what an
installed wheel is tested for (the theme found as package data, the starter's files, the
bundled scenes). A full ``pip install .`` with downloads is `bench/fresh_install.sh`.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest
import yaml
from sitegen_helpers import REPO

from sitegen import DISTRIBUTION

OURS = ("sitegen", "roster", "sims", "located", "__editable__", "_sitegen")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    built = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(out), str(REPO)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert built.returncode == 0, built.stderr[-2000:]
    (found,) = out.glob("*.whl")
    assert found.name.startswith(DISTRIBUTION.replace("-", "_") + "-")
    return found


def _dependencies(into: Path) -> Path:
    """Links to every installed package of this interpreter except sitegen's own, in one
    folder (a .pth line adds it to the new environment: its own .pth files are not run)."""
    into.mkdir()
    seen: set[str] = set()
    for entry in sys.path:
        folder = Path(entry)
        if folder.name not in ("site-packages", "dist-packages") or not folder.is_dir():
            continue
        for item in sorted(folder.iterdir()):
            name = item.name
            if name in seen or name.endswith(".pth") or name.lower().startswith(OURS):
                continue
            if name.lower().startswith(DISTRIBUTION.replace("-", "_")):
                continue
            seen.add(name)
            (into / name).symlink_to(item, target_is_directory=item.is_dir())
    return into


def fresh_env(root: Path) -> dict[str, str]:
    """A new virtual environment at ``root/venv`` with the dependencies visible; returns the
    environment variables that make its ``python3`` and ``sitegen`` the ones run."""
    venv = root / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    purelib = sysconfig.get_path("purelib", vars={"base": str(venv), "platbase": str(venv)})
    deps = _dependencies(root / "deps")
    Path(purelib, "dependencies.pth").write_text(f"{deps}\n", encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    env["VIRTUAL_ENV"] = str(venv)
    env["PIP_NO_INDEX"] = "1"  # everything it needs is here: a download would be a bug
    return env


def run(args: list[str], cwd: Path, env: dict[str, str]) -> subprocess.CompletedProcess:
    done = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{args} failed:\n{done.stdout[-2000:]}\n{done.stderr[-3000:]}"
    return done


def shorten_clips(site: Path) -> None:
    """One simulated second per clip at a small size: the steps still build strictly and
    check every page; rendering at length is tested in tests/test_new_site.py."""
    config = site / "sitegen.yml"
    data = yaml.safe_load(config.read_text(encoding="utf-8"))
    data["sims"].update(size="160x120", fps=10)
    for clip in data["sims"]["clips"]:
        clip.update(seconds=1, speed=1)
    config.write_text(yaml.safe_dump(data, allow_unicode=True), encoding="utf-8")


def test_the_wheel_in_a_fresh_environment_makes_a_site_that_builds(wheel, tmp_path):
    env = fresh_env(tmp_path)
    python = str(tmp_path / "venv/bin/python")
    run([python, "-m", "pip", "install", "-q", "--no-deps", str(wheel)], tmp_path, env)
    where = run([python, "-c", "import sitegen, sys; print(sitegen.__file__)"], tmp_path, env)
    assert where.stdout.startswith(str(tmp_path / "venv")), where.stdout
    run(["sitegen", "new", "s"], tmp_path, env)
    shorten_clips(tmp_path / "s")
    run(["sitegen", "build", "--strict"], tmp_path / "s", env)
    run(["sitegen", "check", "site"], tmp_path / "s", env)
    site = tmp_path / "s/site"
    assert "assets/style.css" in (site / "index.html").read_text(encoding="utf-8")
    # the starter's clip is a replay (sims.formats: [replay]): the glTF and its page script
    assert list(site.glob("clips/*/replay.glb")), "no clip rendered"


def test_the_starters_workflow_steps_pass_from_the_wheel(wheel, tmp_path):
    """``sitegen new --from WHEEL`` writes requirements.txt; the starter's pages.yml and
    check.yml run: steps then install sitegen from it (pip, as on GitHub), build and check."""
    env = fresh_env(tmp_path)
    python = str(tmp_path / "venv/bin/python")
    with zipfile.ZipFile(wheel) as z:
        assert "sitegen/starter/scripts/drive.py" in z.namelist()
    # sitegen new from the wheel's files (not this checkout), without installing it yet
    unpacked = tmp_path / "unpacked"
    zipfile.ZipFile(wheel).extractall(unpacked)
    new = [python, "-c", "import sys; from sitegen.cli import main; sys.exit(main())"]
    run([*new, "new", "s", "--from", str(wheel)], tmp_path, {**env, "PYTHONPATH": str(unpacked)})
    site = tmp_path / "s"
    pin = (site / "requirements.txt").read_text(encoding="utf-8")
    assert f"{DISTRIBUTION} @ {wheel.as_uri()}" in pin.splitlines()
    shorten_clips(site)
    for name in ("pages.yml", "check.yml"):
        workflow = yaml.safe_load((site / ".github/workflows" / name).read_text(encoding="utf-8"))
        for job in workflow["jobs"].values():
            for step in job["steps"]:
                if "run" not in step:
                    continue  # actions only GitHub runs: checkout, setup-python, cache, Pages
                lines = [x for x in step["run"].splitlines() if not x.lstrip().startswith("sudo ")]
                run(["bash", "-eo", "pipefail", "-c", "\n".join(lines)], site, env)
    assert (site / "site/index.html").is_file()
    where = run([python, "-c", "import sitegen; print(sitegen.__file__)"], tmp_path, env)
    assert where.stdout.startswith(str(tmp_path / "venv")), where.stdout
