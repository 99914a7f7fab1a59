"""``-q``/``-v`` as on every sitegen command, for each package's command-line parser.

``verbosity`` is -1 (quiet: informational lines dropped, never errors, warnings or the data the
command exists to print), 0 (default) or 1 (verbose: more detail). Each command says in its help
what the two mean for it.
"""

from __future__ import annotations

import argparse


def add_verbosity(parser: argparse.ArgumentParser, quiet: str, verbose: str) -> None:
    """Add the mutually exclusive ``-q/--quiet`` and ``-v/--verbose`` options to ``parser``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "-q", "--quiet", dest="verbosity", action="store_const", const=-1, default=0, help=quiet
    )
    group.add_argument(
        "-v", "--verbose", dest="verbosity", action="store_const", const=1, help=verbose
    )
