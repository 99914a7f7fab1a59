"""Roster benchmark: parse + validate + emit for 1k, 10k and 100k members.

Why: a department-wide roster (every course, every year) can reach tens of
thousands of students; the site build must stay linear in roster size. The
ratio of 100k to 10k time should be about 10.

Generates course-format TSV rosters (groups of 8, one in ten groups short with
empty slots, 1% of ids annotated, 1% of accounts needing an alias) plus a
corrections file, then times `load_roster` (parse, corrections, validation) and
the emitters (`to_dict`, `to_json`, `to_html`). Reports the best of several runs
(CPU time of this process, so other load on a shared machine inflates the
figures as little as possible), and the same with CPython's cyclic GC paused
(see `time_once`).

    python bench/roster_bench.py [--sizes 1000 10000 100000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import gc
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from roster import load_roster  # noqa: E402
from roster.emit import to_html, to_json  # noqa: E402

GROUP_SIZE = 8


def write_roster(directory: Path, members: int) -> tuple[Path, Path]:
    """Write a roster with `members` students and its corrections file; return both paths."""
    lines = []
    aliases = []
    sid = 0
    group = 0
    while sid < members:
        group += 1
        size = min(GROUP_SIZE - (2 if group % 10 == 0 else 0), members - sid)
        fields = [f"stage3_ag{group}"]
        for _ in range(size):
            sid += 1
            student = f"4{sid:07d}"
            account = student
            if sid % 100 == 7:
                account = f"a{student}"
                aliases.append(f'  "{student}": "{account}"')
            mark = "*" if sid % 100 == 3 else ""
            fields += [student + mark, account]
        fields += [""] * (2 * (GROUP_SIZE - size))  # empty slots, as the course file has
        lines.append("\t".join(fields))
    roster = directory / f"roster_{members}.txt"
    roster.write_text("\n".join(lines) + "\n", encoding="utf-8")
    corrections = directory / f"roster_{members}.corrections.yml"
    corrections.write_text(
        "aliases:\n" + "\n".join(aliases) + '\ngroup_names:\n  - {replace: "_", with: "-"}\n',
        encoding="utf-8",
    )
    return roster, corrections


def time_once(
    roster: Path, corrections: Path, gc_paused: bool = False
) -> tuple[float, float, int, int]:
    """(load seconds, emit seconds, members, output bytes) for one run.

    With `gc_paused` the cyclic garbage collector is off during the run: its
    full collections scan the whole heap, so they cost more per member on a big
    heap than on a small one. Timing both shows what is CPython's and what is ours.
    """
    gc.collect()
    if gc_paused:
        gc.disable()
    try:
        t0 = time.process_time()
        result = load_roster(roster, corrections=corrections)
        t1 = time.process_time()
        data = result.to_dict()
        out = to_json(result) + to_html(result)
        t2 = time.process_time()
    finally:
        gc.enable()
    assert not result.errors, result.errors[:3]
    members = sum(len(g["members"]) for g in data["groups"])
    return t1 - t0, t2 - t1, members, len(out.encode("utf-8"))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1_000, 10_000, 100_000])
    parser.add_argument("--repeat", type=int, default=3, help="runs per size; the best is reported")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory(prefix="roster-bench-") as tmp:
        for size in args.sizes:
            roster, corrections = write_roster(Path(tmp), size)
            runs = [time_once(roster, corrections) for _ in range(args.repeat)]
            paused = [time_once(roster, corrections, gc_paused=True) for _ in range(args.repeat)]
            load_s = min(r[0] for r in runs)
            emit_s = min(r[1] for r in runs)
            paused_s = min(r[0] + r[1] for r in paused)
            members, out_bytes = runs[0][2], runs[0][3]
            assert members == size, (members, size)
            rows.append((size, roster.stat().st_size, load_s, emit_s, paused_s, out_bytes))
    print(
        f"{'members':>8} {'input':>9} {'load s':>8} {'emit s':>8} {'total s':>8} "
        f"{'us/member':>10} {'no-GC s':>8} {'output':>9}"
    )
    for size, in_bytes, load_s, emit_s, paused_s, out_bytes in rows:
        total = load_s + emit_s
        print(
            f"{size:>8} {in_bytes / 1024:>7.0f}kB {load_s:>8.3f} {emit_s:>8.3f} {total:>8.3f} "
            f"{total / size * 1e6:>10.1f} {paused_s:>8.3f} {out_bytes / 1024:>7.0f}kB"
        )
    totals = {row[0]: row[2] + row[3] for row in rows}
    paused = {row[0]: row[4] for row in rows}
    if 10_000 in totals and 100_000 in totals:
        print(
            f"ratio 100k/10k: {totals[100_000] / totals[10_000]:.1f} "
            f"(cyclic GC paused: {paused[100_000] / paused[10_000]:.1f}; linear = 10)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
