"""Python environments and client libraries the remote API transport tests need from PyPI.

They are built once per machine in a cache folder (``$SITEGEN_TEST_CACHE``, else
``~/.cache/sitegen-tests``; CI runs pytest without its own cache) and reused; a test that
cannot have one (no network, PyPI unreachable) is skipped, saying why.
"""

from __future__ import annotations

import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

#: CoppeliaSim's legacy client library (extApi.c) compiled into a wheel on PyPI: DQ Robotics'
#: V-REP interface links it and exports its simx* C functions unchanged.
EXTAPI_WHEEL = "dqrobotics-interface-coppeliasim-vrep==0.25.6.24"


def cache_dir() -> Path:
    import os

    folder = Path(os.environ.get("SITEGEN_TEST_CACHE") or Path.home() / ".cache" / "sitegen-tests")
    folder = folder / "remote-api-foreign"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _run(cmd: list[str], what: str, timeout: float = 600) -> None:
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as exc:
        pytest.skip(f"{what}: {exc}")
    if done.returncode != 0:
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["?"]
        pytest.skip(f"{what} failed (offline?): {tail[0]}")


def python_env(cache: Path, name: str, requirements: list[str]) -> Path:
    """The interpreter of a virtual environment holding ``requirements`` (built once)."""
    folder = cache / name
    python = folder / "bin" / "python"
    done = folder / ".complete"
    if done.is_file() and python.exists():
        return python
    venv.EnvBuilder(with_pip=True, clear=True).create(folder)
    _run(
        [str(python), "-m", "pip", "install", "-q", "--disable-pip-version-check", *requirements],
        f"pip install {' '.join(requirements)}",
    )
    done.write_text("\n".join(requirements), encoding="utf-8")
    return python


def extapi_library(cache: Path) -> Path:
    """A shared library exporting CoppeliaSim's legacy client functions (simxStart, ...)."""
    folder = cache / "extapi"
    found = sorted(folder.glob("**/_core*.so"))
    if found:
        return found[0]
    folder.mkdir(parents=True, exist_ok=True)
    _run(
        [sys.executable, "-m", "pip", "download", "-q", "--no-deps", "--only-binary=:all:",
         "-d", str(folder), EXTAPI_WHEEL],
        f"pip download {EXTAPI_WHEEL}",
    )  # fmt: skip
    for wheel in folder.glob("*.whl"):
        with zipfile.ZipFile(wheel) as z:
            z.extractall(folder / "unpacked")
    found = sorted(folder.glob("**/_core*.so"))
    if not found:
        pytest.skip(f"{EXTAPI_WHEEL} holds no compiled library for this platform")
    return found[0]
