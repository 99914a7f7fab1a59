"""Benchmark ``sitegen build`` against Hugo and MkDocs on one synthetic 1000-page corpus.

Run: ``python bench/build_bench.py`` (needs ``pip install -e .[bench]`` for MkDocs and Debian's
``apt-get install hugo``; a missing peer is reported and skipped). Everything runs in one go on
this machine, interleaved round by round, and each figure is the median over the rounds, so
the ratios are comparable even though absolute times vary between machines and with load.

Measured, every run cold (output folder AND cache removed first, for every tool):

* sitegen cold vs Hugo rendering the *same collapsed menu* (top level plus the open branch,
  the page marked) — the like-for-like peer;
* sitegen cold vs Hugo with every page in every menu (what the old bench compared against);
* sitegen cold vs MkDocs;
* sitegen no-op rebuild and one-page edit, vs Hugo full menu (cold; Hugo has no cache);
* peak memory of a sitegen cold build at ``--memory-pages`` pages (default 5000): the largest
  total memory (proportional set size, shared pages counted once) of its whole process tree,
  workers included, sampled every 10 ms; at least the largest single process's peak RSS.

What "cold" keeps: each tool's own caches and output are removed before every cold run, but the
tools themselves are installed as a user has them. For the Python tools (sitegen, MkDocs) that
means compiled bytecode, which ``pip install`` writes at install time: the bench runs them with
``PYTHONDONTWRITEBYTECODE`` unset and ``PYTHONPYCACHEPREFIX`` under ``bench/_work`` (so nothing is
written into the repository), after one untimed warm-up run of every tool (which also fills the
operating system's file cache for every tool alike).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import random
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

WORK = Path(__file__).resolve().parent / "_work"
PROSE = (
    "齒輪的方向與速度需要在設計時一併考慮, 錯誤排解時先確認傳動比. 協同設計以 GitHub 倉儲管理, "
    "每位組員在 cd2021 倉儲中撰寫週報. "
    "機構模擬使用 CoppeliaSim 與 pybullet, 馬達以位置控制驅動手臂. "
    "產品簡化後重新繪製 2D 工程圖與 3D 爆炸圖, 並以影片說明組裝流程. "
)
#: One code block per page, different on every page (a build may reuse the highlighting of a
#: block it has seen: identical blocks on every page would flatter it).
CODE = (
    "```python\nimport sim as vrep\n"
    "clientID = vrep.simxStart('127.0.0.1', {port}, True, True, 5000, 5)\n"
    "for i in range({n}):\n    print(i * {k}, 'w{w}-{i}')\n```\n"
)
TABLE = (
    "| 項目 | 數值 | 說明 |\n|---|---|---|\n"
    "| 速度 | 2 rad/s | 最大 |\n| 步進 | 0.5 rad/s | 每次 |\n"
)


def make_corpus(root: Path, pages: int = 1000, weeks: int = 18, seed: int = 1) -> list[Path]:
    """Write ``pages`` Markdown files in ``weeks`` week folders under three stages."""
    rng = random.Random(seed)
    if root.exists():
        shutil.rmtree(root)
    files = []
    (root).mkdir(parents=True)
    (root / "index.md").write_text("# 首頁\n\n" + PROSE * 3, encoding="utf-8")
    per_week = (pages - 1 - weeks - 3) // weeks
    n = 1
    for w in range(1, weeks + 1):
        stage = 1 if w <= 4 else 2 if w <= 9 else 3
        sdir = root / f"stage-{stage}"
        if not (sdir / "index.md").exists():
            sdir.mkdir(parents=True, exist_ok=True)
            (sdir / "index.md").write_text(f"# Stage {stage}\n\n{PROSE}", encoding="utf-8")
            n += 1
        wdir = sdir / f"w{w}"
        wdir.mkdir()
        (wdir / "index.md").write_text(f"# W{w}\n\n{PROSE}", encoding="utf-8")
        n += 1
        for i in range(per_week):
            body = [f"# 第 {w} 週 頁面 {i + 1}\n"]
            for h in range(3):
                body.append(f"## 小節 {h + 1}\n\n" + PROSE * rng.randint(2, 5))
                code = CODE.format(port=19997 + i, n=h + w, k=i + 2, w=w, i=i)
                body.append(code if h == 1 else TABLE)
            path = wdir / f"page-{i + 1:03d}.md"
            path.write_text("\n".join(body), encoding="utf-8")
            files.append(path)
            n += 1
    while n < pages:
        path = root / f"stage-3/w{weeks}/extra-{n}.md"
        path.write_text(f"# 補充 {n}\n\n{PROSE}", encoding="utf-8")
        files.append(path)
        n += 1
    return files


def _tree_mb(pid: int) -> float:
    """Memory of ``pid`` and all its descendants, in MB: the sum of their proportional set
    sizes (Linux ``smaps_rollup``), so pages a forked worker shares with the build are counted
    once, not once per process."""
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        try:
            with open(f"/proc/{p}/smaps_rollup", encoding="ascii", errors="replace") as fh:
                for line in fh:
                    if line.startswith("Pss:"):
                        total += int(line.split()[1])
                        break
            with open(f"/proc/{p}/task/{p}/children", encoding="ascii") as fh:
                todo.extend(int(c) for c in fh.read().split())
        except (OSError, ValueError):
            continue
    return total / 1024


def timed(cmd: list[str], cwd: Path | None = None) -> tuple[float, float]:
    """Run a command; return (seconds, peak MB: the largest total memory of its process tree
    seen every 10 ms, or the largest single process's peak if that is more)."""
    start = time.perf_counter()
    proc = subprocess.Popen(
        cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=installed_env()
    )
    peak, done = [0.0], threading.Event()

    def sample() -> None:
        while not done.wait(0.01):
            peak[0] = max(peak[0], _tree_mb(proc.pid))

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    _pid, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    done.set()
    sampler.join()
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}\n{proc.stderr.read().decode()[-2000:]}")
    return seconds, max(peak[0], usage.ru_maxrss / 1024)


def installed_env() -> dict[str, str]:
    """The environment of every timed command: Python tools keep their compiled bytecode, as
    an installed package does (see the module's docstring)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(WORK / "pycache")
    return env


_TITLE = re.compile(r"^#\s+(.+)$", re.M)


def hugo_site(corpus: Path, dest: Path, menu: str) -> Path:
    """A minimal Hugo project over the same Markdown (titles from each page's first heading).

    ``menu="collapsed"``: the menu sitegen renders (top level; the current page's branch open;
    the page marked current; a closed section shows a "more" mark); ``menu="full"``: every page
    in every menu."""
    if dest.exists():
        shutil.rmtree(dest)
    (dest / "layouts/_default").mkdir(parents=True)
    shutil.copytree(corpus, dest / "content")
    for md in (dest / "content").rglob("*.md"):
        text = md.read_text(encoding="utf-8")
        m = _TITLE.search(text)
        title = (m.group(1) if m else md.stem).replace('"', "'")
        md.write_text(f'---\ntitle: "{title}"\n---\n{text}', encoding="utf-8")
        if md.name == "index.md":
            md.rename(md.with_name("_index.md"))
    (dest / "hugo.toml").write_text(
        'baseURL = "http://127.0.0.1/"\ntitle = "bench"\n'
        'disableKinds = ["taxonomy", "term", "RSS", "sitemap"]\n',
        encoding="utf-8",
    )
    if menu == "full":
        nav = '{{ template "tree" .Site.Home }}'
        tree = (
            '{{ define "tree" }}<ul>{{ range .Sections }}<li><a href="{{ .RelPermalink }}">'
            '{{ .Title }}</a>{{ template "tree" . }}</li>{{ end }}{{ range .RegularPages }}<li>'
            '<a href="{{ .RelPermalink }}">{{ .Title }}</a></li>{{ end }}</ul>{{ end }}'
        )
    else:
        nav = (
            '<ul><li><a href="{{ .Site.Home.RelPermalink }}">{{ .Site.Home.Title }}</a></li>'
            '{{ range .Site.Home.Pages }}{{ template "item" (dict "n" . "cur" $) }}{{ end }}</ul>'
        )
        tree = (
            '{{ define "item" }}{{ $n := .n }}{{ $cur := .cur }}'
            "{{ $open := or (eq $n $cur) ($n.IsAncestor $cur) }}"
            '<li{{ if eq $n $cur }} class="current"{{ else if $open }} class="open"{{ end }}>'
            '<a href="{{ $n.RelPermalink }}">{{ $n.Title }}</a>'
            '{{ if and $n.IsSection (not $open) }}<span class="more">›</span>{{ end }}'
            "{{ if and $n.IsSection $open }}<ul>{{ range $n.Pages }}"
            '{{ template "item" (dict "n" . "cur" $cur) }}{{ end }}</ul>{{ end }}</li>{{ end }}'
        )
    page = (
        "<!DOCTYPE html><html><head><title>{{ .Title }}</title></head><body><nav>"
        + nav
        + "</nav><main><h1>{{ .Title }}</h1>{{ .Content }}"
        '{{ with .PrevInSection }}<a href="{{ .RelPermalink }}">{{ .Title }}</a>{{ end }}'
        "</main></body></html>" + tree
    )
    for name in ("single.html", "list.html"):
        (dest / "layouts/_default" / name).write_text(page, encoding="utf-8")
    return dest


def mkdocs_site(corpus: Path, dest: Path) -> Path:
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    shutil.copytree(corpus, dest / "docs")
    (dest / "mkdocs.yml").write_text(
        "site_name: bench\nuse_directory_urls: false\n", encoding="utf-8"
    )
    return dest


@dataclass
class Runner:
    """One tool's cold build: what to remove first, the command, where to run it."""

    name: str
    cmd: list[str]
    clear: list[Path]
    cwd: Path | None = None
    times: list[float] = field(default_factory=list)
    mems: list[float] = field(default_factory=list)

    def run(self, record: bool = True) -> None:
        for path in self.clear:
            shutil.rmtree(path, ignore_errors=True)
        secs, mem = timed(self.cmd, self.cwd)
        if record:
            self.times.append(secs)
            self.mems.append(mem)

    def shell(self) -> str:
        rm = f"rm -rf {' '.join(shlex.quote(str(p)) for p in self.clear)} && " if self.clear else ""
        cd = f"cd {shlex.quote(str(self.cwd))} && " if self.cwd else ""
        prefix = shlex.quote(str(WORK / "pycache"))
        env = f"env -u PYTHONDONTWRITEBYTECODE PYTHONPYCACHEPREFIX={prefix} "
        return f"{rm}{cd}{env}{shlex.join(self.cmd)}"


def sitegen_cmd(corpus: Path, out: Path) -> list[str]:
    return [
        sys.executable,
        "-m",
        "sitegen",
        "build",
        "--source",
        str(corpus),
        "--output",
        str(out),
    ]


def plain_cache(out: Path) -> Path:
    """Where ``sitegen build`` keeps the cache for a plain folder (sitegen/build.py)."""
    return out.parent / f".sitegen-cache-{out.name}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pages", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds (median)")
    parser.add_argument("--memory-pages", type=int, default=5000, help="0 skips the run")
    parser.add_argument("--skip-peers", action="store_true")
    args = parser.parse_args()
    corpus = WORK / "corpus"
    files = make_corpus(corpus, args.pages)
    out = WORK / "site"
    cache = plain_cache(out)
    cold = Runner("sitegen cold", sitegen_cmd(corpus, out), [out, cache])
    runners = [cold]
    if not args.skip_peers:
        if shutil.which("hugo"):
            for menu, label in (("collapsed", "hugo same menu"), ("full", "hugo full menu")):
                site = hugo_site(corpus, WORK / f"hugo-{menu}", menu)
                dest = WORK / f"hugo-{menu}-out"
                cmd = ["hugo", "--quiet", "--ignoreCache", "-d", str(dest)]
                runners.append(Runner(label, cmd, [dest, site / "resources"], site))
        else:
            print("hugo not found: apt-get install hugo", file=sys.stderr)
        if importlib.util.find_spec("mkdocs"):
            site = mkdocs_site(corpus, WORK / "mkdocs")
            dest = WORK / "mkdocs-out"
            cmd = [sys.executable, "-m", "mkdocs", "build", "-q", "-d", str(dest)]
            runners.append(Runner("mkdocs", cmd, [dest], site))
        else:
            print("mkdocs not installed: pip install -e .[bench]", file=sys.stderr)
    for runner in runners:  # warm-up, not timed: bytecode compiled, files in the OS cache
        runner.run(record=False)
    for r in range(args.rounds):  # interleaved, the order rotating each round
        k = r % len(runners)
        for runner in runners[k:] + runners[:k]:
            runner.run()
    noop = Runner("sitegen no-op", cold.cmd, [])
    edit = Runner("sitegen one-page edit", cold.cmd, [])
    target = files[len(files) // 2]
    original = target.read_text(encoding="utf-8")
    for r in range(args.rounds):
        cold.run()  # a fresh site and cache, then the two incremental runs on top of it
        noop.run()
        target.write_text(original + f"\n一行修改 {r}.\n", encoding="utf-8")
        edit.run()
    target.write_text(original, encoding="utf-8")
    mem_row = None
    if args.memory_pages:
        big = WORK / "corpus-big"
        make_corpus(big, args.memory_pages)
        big_out = WORK / "site-big"
        mem_row = Runner(
            f"sitegen cold {args.memory_pages} pages",
            sitegen_cmd(big, big_out),
            [big_out, plain_cache(big_out)],
        )
        mem_row.run()

    med = {r.name: statistics.median(r.times) for r in [*runners, noop, edit]}
    html = sum(1 for _ in out.rglob("*.html"))
    print(
        f"corpus: {args.pages} Markdown pages in 18 week folders ({html} HTML files written); "
        f"{os.cpu_count()} cores; median of {args.rounds} interleaved rounds; every cold run "
        "with output and cache removed"
    )
    print(f"{'run':34} {'seconds':>8} {'peak MB':>8}  ratio")
    for r in [*runners, noop, edit]:
        print(f"{r.name:34} {med[r.name]:8.2f} {max(r.mems):8.0f}")
    if mem_row is not None:
        print(f"{mem_row.name:34} {mem_row.times[0]:8.2f} {mem_row.mems[0]:8.0f}")
    print()
    goals = [
        ("sitegen cold", "hugo same menu", 1.0),
        ("sitegen cold", "hugo full menu", None),
        ("sitegen cold", "mkdocs", None),
        ("sitegen no-op", "hugo full menu", None),
        ("sitegen one-page edit", "hugo full menu", 0.05),
    ]
    for mine, peer, goal in goals:
        if peer in med:
            ratio = med[mine] / med[peer]
            want = f"  (goal <= {goal}x: {'met' if ratio <= goal else 'NOT met'})" if goal else ""
            print(f"{mine:22} / {peer:15} = {ratio:6.3f}x{want}")
    if mem_row is not None:
        ok = "met" if mem_row.mems[0] <= 150 else "NOT met"
        print(
            f"peak memory at {args.memory_pages} pages = {mem_row.mems[0]:.0f} MB  "
            f"(goal <= 150 MB: {ok})"
        )
    print("\nreproduce everything: python bench/build_bench.py " + shlex.join(sys.argv[1:]))
    print("the single runs (from the repository root):")
    for r in [*runners, noop, edit] + ([mem_row] if mem_row else []):
        print(f"  {r.name}: {r.shell()}")
    print(f"  (one-page edit: append a line to {target.relative_to(WORK.parent.parent)} first)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
