"""``python -m sims.lua``: run.py's commands in a fenced child with a wall-clock limit.

Why here: a scene script can hang in C code that no instruction budget reaches (the remote
API and clip builds have their wall-clock kills; this command has its own now, like them), and
its scripts get the same fence as every other run (sims/remote_api/isolate.py).
``--timeout S`` (default 600 wall seconds, at most a week) may come anywhere on the line.
"""

import sys

from .run import main

DEFAULT_TIMEOUT = 600.0
MAX_TIMEOUT = 7 * 86400.0


def _timeout(argv: list[str]) -> tuple[float | None, list[str], str | None]:
    """(limit, the other arguments, an error line or None)."""
    rest, limit = [], DEFAULT_TIMEOUT
    args = iter(argv)
    for arg in args:
        if arg == "--timeout" or arg.startswith("--timeout="):
            text = arg.partition("=")[2] if "=" in arg else next(args, "")
            try:
                limit = float(text)
            except ValueError:
                limit = float("nan")
            if not 0 < limit <= MAX_TIMEOUT:
                return (
                    None,
                    rest,
                    (
                        f"error: --timeout must be a positive number of seconds, at most "
                        f"{MAX_TIMEOUT:g} (a week), got {text or 'nothing'}"
                    ),
                )
        else:
            rest.append(arg)
    return limit, rest, None


def run(argv: list[str]) -> int:
    from sims.remote_api.isolate import call_isolated

    limit, rest, problem = _timeout(argv)
    if problem or limit is None:
        print(problem, file=sys.stderr)
        return 2
    try:
        return call_isolated(lambda: main(rest), limit, "python -m sims.lua")
    except TimeoutError:
        print(
            f"error: stopped: the run did not end within its wall-clock limit of {limit:g} s "
            "(--timeout); its process and every process it started were killed",
            file=sys.stderr,
        )
        return 124


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
