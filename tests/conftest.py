"""Test setup: helpers importable, and no silent skips under CI.

Several tests read the course's shared data (``../shared``: the real roster, the course
scripts, cmsimde sites). Locally they skip when it is absent; under CI a missing folder is an
error, so a green run always means those tests ran.
"""

import os
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
SHARED = HERE.parents[1] / "shared"


def pytest_configure(config: pytest.Config) -> None:
    if os.environ.get("CI") and not (SHARED / "data").is_dir():
        raise pytest.UsageError(f"CI is set but the course's shared data is missing: {SHARED}")
