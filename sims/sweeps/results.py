"""results.csv and results.jsonl: one row a run, in run-index order.

results.csv holds what the runs measured and nothing about where or how fast they ran, so it
is byte for byte the same whichever executor ran the sweep and however many workers it had:
index, seed, the arguments, status, exit code, simulated seconds, the results the runs reported
(``RESULT`` lines and result files, columns in the order they first appear), the final pose
and joints, and the error. results.jsonl holds every record whole, wall-clock seconds, attempts
and the worker that ran it included. Numbers are written as Python's shortest round-trip form.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from .one_run import RunRecord

FIXED = ("index", "seed")
STATUS = ("status", "exit_code", "sim_seconds", "simulations")
POSE = ("x", "y", "z", "heading")
CSV_NAME = "results.csv"
JSONL_NAME = "results.jsonl"


def cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (int, str)):
        return str(value)
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def _ordered(keys: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(keys))


def columns(records: list[RunRecord]) -> tuple[list[str], list[str], list[str], list[str]]:
    """Argument names, result keys, final-pose keys and joint names, first-seen order."""
    args = _ordered(k for r in records for k in r.args)
    results = _ordered(k for r in records for k in r.results)
    pose = [k for k in POSE if any(k in r.final for r in records)]
    joints = _ordered(k for r in records for k in r.final.get("joints", {}))
    return args, results, pose, joints


def result_column(key: str, taken: set[str]) -> str:
    """A result's column: its own name unless a fixed column or an argument has it."""
    return key if key not in taken else f"result_{key}"


def table(records: list[RunRecord]) -> tuple[list[str], list[list[str]]]:
    """The header and rows of results.csv, in run-index order."""
    records = sorted(records, key=lambda r: r.index)
    args, results, pose, joints = columns(records)
    taken = set(FIXED) | set(STATUS) | set(args) | {"error"}
    taken |= {f"final_{k}" for k in [*pose, *joints]}
    header = [
        *FIXED,
        *args,
        *STATUS,
        *(result_column(k, taken) for k in results),
        *(f"final_{k}" for k in pose),
        *(f"final_{k}" for k in joints),
        "error",
    ]
    rows = []
    for r in records:
        joint_values = r.final.get("joints", {})
        rows.append(
            [
                cell(r.index),
                cell(r.seed),
                *(cell(r.args.get(k)) for k in args),
                r.status,
                cell(r.exit_code),
                cell(r.sim_seconds),
                cell(r.simulations),
                *(cell(r.results.get(k)) for k in results),
                *(cell(r.final.get(k)) for k in pose),
                *(cell(joint_values.get(k)) for k in joints),
                r.error,
            ]
        )
    return header, rows


def csv_text(records: list[RunRecord]) -> str:
    header, rows = table(records)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return buffer.getvalue()


VARYING = ("wall_seconds", "attempts", "host")  # what differs from one run of a sweep to the next


def jsonl_text(records: list[RunRecord], varying: bool = True) -> str:
    """Every record whole; ``varying=False`` leaves out :data:`VARYING` (a site's copy, which
    must be the same bytes whenever the same sweep is built)."""
    lines = []
    for r in sorted(records, key=lambda r: r.index):
        data = r.to_json()
        if not varying:
            data = {k: v for k, v in data.items() if k not in VARYING}
        lines.append(json.dumps(data, ensure_ascii=False, separators=(",", ":")) + "\n")
    return "".join(lines)


def write(out_dir: Path, records: list[RunRecord]) -> tuple[Path, Path]:
    """Write both files (each whole, then renamed into place); returns their paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    records = sorted(records, key=lambda r: r.index)
    paths = (out_dir / CSV_NAME, out_dir / JSONL_NAME)
    for path, text in zip(paths, (csv_text(records), jsonl_text(records)), strict=True):
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(text, encoding="utf-8")
        tmp.replace(path)
    return paths


def read_jsonl(path: Path) -> list[RunRecord]:
    out = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.strip():
            out.append(RunRecord.from_json(json.loads(line)))
    return out
