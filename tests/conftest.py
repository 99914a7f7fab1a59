"""Test setup: the helper modules (``sitegen_helpers``, ``shared_data``) importable.

Tests that read the course's shared data (``../shared``: the real roster, the course scripts,
cmsimde sites) ask for it through :func:`shared_data.shared` or the ``needs_shared`` mark:
without the folder each such test skips with a reason naming the missing path; with ``CI`` set
each one fails instead, so a green CI run means they ran. Every other test runs either way (the
repository's own site needs nothing outside the repository).
"""

import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers",
        "needs_shared(*parts): the test reads ../shared/<parts>; skips without it, fails under CI",
    )


def pytest_runtest_setup(item: pytest.Item) -> None:
    """``@pytest.mark.needs_shared("data", "x.txt")``: checked per test, when it runs."""
    from shared_data import shared

    for mark in item.iter_markers(name="needs_shared"):
        shared(*mark.args)
