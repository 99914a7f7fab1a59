"""What a sweep runs: numbered runs, each with its arguments and its own deterministic seed.

Runs come from seeds (``--seeds 0:1000``), a grid (``--grid gain=0.5,1,2``, every combination,
the first name varying slowest) and an argument file (``--args-file runs.csv``: a header of
names, one row a run); given together they multiply, seeds outermost. A run's seed is the seed
it was given (``--seeds``, a ``seed`` column or grid name), else derived from the sweep's seed
and the run's index, so the same sweep gives the same seeds on any executor and any number of
workers. A script sees its arguments twice: in ``sys.argv`` as ``--NAME=VALUE`` (argparse reads
them) and as environment variables ``SWEEP_NAME`` (upper case), beside ``SWEEP_INDEX``,
``SWEEP_SEED`` and ``SWEEP_RESULT_FILE`` (where it may write a JSON object of results).

Bad input is a :class:`located.diagnostics.LocatedError` naming the file (or option), the line
and the field.
"""

from __future__ import annotations

import csv
import hashlib
import io
import itertools
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from located.diagnostics import Diagnostic, LocatedError

NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
SEED_NAME = "seed"  # an argument of this name sets the run's seed
MAX_RUNS = 1_000_000
ENV_PREFIX = "SWEEP_"
RESULT_FILE_ENV = "SWEEP_RESULT_FILE"


@dataclass(frozen=True)
class RunSpec:
    """One run of a sweep: its index (results are ordered by it), seed and arguments."""

    index: int
    seed: int
    args: tuple[tuple[str, str], ...] = ()

    def argv(self) -> list[str]:
        """The script's ``sys.argv[1:]``: ``--NAME=VALUE`` for every argument but the seed."""
        return [f"--{name}={value}" for name, value in self.args if name != SEED_NAME]

    def env(self) -> dict[str, str]:
        """Environment variables the run's script sees (the result file's is added later)."""
        out = {f"{ENV_PREFIX}{name.upper()}": value for name, value in self.args}
        out[f"{ENV_PREFIX}INDEX"] = str(self.index)
        out[f"{ENV_PREFIX}SEED"] = str(self.seed)
        return out


def option_error(option: str, message: str) -> LocatedError:
    """A bad command-line value: the option stands in for the file."""
    return LocatedError(Diagnostic(option, None, "", message))


def derived_seed(sweep_seed: int, index: int) -> int:
    """A run's seed from the sweep's seed and its index: the same on every executor, spread
    over 31 bits so neighbouring runs do not get neighbouring seeds."""
    digest = hashlib.sha256(f"sitegen-sweep:{sweep_seed}:{index}".encode()).digest()
    return int.from_bytes(digest[:4], "big") & 0x7FFFFFFF


def parse_seeds(text: str, option: str = "--seeds") -> list[int]:
    """``A:B`` (A to B-1), ``A:B:STEP`` or a comma list ``1,5,9``."""
    try:
        if ":" in text:
            parts = [int(p) for p in text.split(":")]
            if len(parts) not in (2, 3) or (len(parts) == 3 and parts[2] == 0):
                raise ValueError
            seeds = list(range(*parts))
        else:
            seeds = [int(p) for p in text.split(",") if p.strip()]
    except ValueError:
        raise option_error(option, f"{text!r}: give START:STOP[:STEP] or a list 1,5,9") from None
    if not seeds:
        raise option_error(option, f"{text!r} holds no seed")
    if len(seeds) > MAX_RUNS:
        raise option_error(option, f"{text!r}: more than {MAX_RUNS} seeds")
    return seeds


def parse_grid(items: Sequence[str], option: str = "--grid") -> list[tuple[str, list[str]]]:
    """``NAME=a,b,c`` items, in the order given."""
    out: list[tuple[str, list[str]]] = []
    for item in items:
        name, eq, values = item.partition("=")
        name = name.strip()
        if not eq or not NAME.match(name):
            raise option_error(option, f"{item!r}: give NAME=value,value,... (NAME a Python name)")
        if name in (n for n, _ in out):
            raise option_error(option, f"{name!r} is given twice")
        listed = [v.strip() for v in values.split(",")]
        if not all(listed):
            raise option_error(option, f"{item!r}: an empty value")
        out.append((name, listed))
    return out


def read_args_file(path: str | Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """A CSV file: a header of names, one row a run. Returns the names and (line, values)."""
    label = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        message = getattr(exc, "strerror", None) or str(exc)
        raise LocatedError(Diagnostic(label, None, "", f"cannot read: {message}")) from None
    reader = csv.reader(io.StringIO(text))
    header: list[str] | None = None
    rows: list[tuple[int, list[str]]] = []
    try:
        for row in reader:
            line = reader.line_num
            if not any(cell.strip() for cell in row):
                continue
            cells = [cell.strip() for cell in row]
            if header is None:
                for column, name in enumerate(cells, 1):
                    if not NAME.match(name):
                        raise LocatedError(
                            Diagnostic(label, line, f"column {column}", f"{name!r} is not a name")
                        )
                    if cells.index(name) != column - 1:
                        raise LocatedError(
                            Diagnostic(label, line, name, "the column is named twice")
                        )
                header = cells
                continue
            if len(cells) != len(header):
                raise LocatedError(
                    Diagnostic(label, line, "row", f"{len(cells)} values for {len(header)} columns")
                )
            rows.append((line, cells))
    except csv.Error as exc:
        raise LocatedError(Diagnostic(label, reader.line_num, "row", str(exc))) from None
    if header is None or not rows:
        raise LocatedError(Diagnostic(label, None, "", "no runs: a header row and one row a run"))
    if len(rows) > MAX_RUNS:
        raise LocatedError(Diagnostic(label, None, "", f"more than {MAX_RUNS} rows"))
    return header, rows


def _seed_value(value: str, where: Diagnostic) -> int:
    try:
        return int(value)
    except ValueError:
        raise LocatedError(
            Diagnostic(where.file, where.line, where.field, f"{value!r} is not a whole number")
        ) from None


def plan_runs(
    seeds: Iterable[int] | None = None,
    grid: Sequence[tuple[str, Sequence[str]]] = (),
    args_file: str | Path | None = None,
    sweep_seed: int = 0,
) -> list[RunSpec]:
    """Every run of the sweep, numbered from 0: seeds x grid x argument-file rows."""
    seed_list: list[int | None] = list(seeds) if seeds is not None else [None]
    names = [n for n, _ in grid]
    file_names: list[str] = []
    file_rows: list[tuple[int | None, list[str]]] = [(None, [])]
    if args_file is not None:
        file_names, read = read_args_file(args_file)
        file_rows = list(read)  # type: ignore[arg-type]
        clash = set(file_names) & set(names)
        if clash:
            raise option_error("--grid", f"{', '.join(sorted(clash))} also in {args_file}")
    total = len(seed_list) * len(file_rows)
    for _, values in grid:
        total *= len(values)
    if total > MAX_RUNS:
        raise option_error("--seeds", f"{total} runs: more than {MAX_RUNS}")
    if seeds is not None and SEED_NAME in [*names, *file_names]:
        raise option_error("--seeds", "the runs' seeds are also given as an argument 'seed'")
    runs: list[RunSpec] = []
    combos = list(itertools.product(*(values for _, values in grid)))
    for seed in seed_list:
        for combo in combos:
            for line, row in file_rows:
                args = tuple(zip(names, combo, strict=True)) + tuple(
                    zip(file_names, row, strict=True)
                )
                index = len(runs)
                run_seed = derived_seed(sweep_seed, index) if seed is None else seed
                for name, value in args:
                    if name == SEED_NAME:
                        where = (
                            Diagnostic("--grid", None, "", "")
                            if line is None or name in names
                            else Diagnostic(str(args_file), line, SEED_NAME, "")
                        )
                        run_seed = _seed_value(value, where)
                runs.append(RunSpec(index, run_seed, args))
    return runs
