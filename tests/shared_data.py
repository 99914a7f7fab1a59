"""The course's shared data (``../shared`` beside the checkout), for tests only.

Tests that read course material call :func:`shared` (or use the ``needs_shared`` mark). Without
the folder they skip with a reason naming what is missing; when ``CI`` is set they fail instead,
so a green CI run always means those tests ran.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

SHARED = Path(__file__).resolve().parents[1].parent / "shared"


def _missing(what: Path) -> None:
    reason = f"course data not present: {what} (clone the shared folder beside the repository)"
    if os.environ.get("CI"):
        pytest.fail(f"CI is set but {reason}", pytrace=False)
    pytest.skip(reason)


def shared(*parts: str) -> Path:
    """The path of ``../shared/<parts>``; skips (or fails under CI) when it does not exist."""
    path = SHARED.joinpath(*parts)
    if not path.exists():
        _missing(path)
    return path


def have_shared(*parts: str) -> bool:
    return SHARED.joinpath(*parts).exists()
