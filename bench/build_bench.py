"""Benchmark ``sitegen build`` against Hugo and MkDocs on one synthetic 1000-page corpus.

Run: ``python bench/build_bench.py`` (needs ``pip install mkdocs`` and Debian's ``hugo``; a
missing peer is reported and skipped). Everything runs in one go on this machine, so the
ratios are comparable even though absolute times vary between machines.

Measured: sitegen cold (empty cache), no-op rebuild, one-page-edit rebuild, peak memory;
Hugo (a minimal layout with the full menu on every page) and MkDocs on the same Markdown.
"""

from __future__ import annotations

import argparse
import os
import random
import shutil
import subprocess
import sys
import time
from pathlib import Path

WORK = Path(__file__).resolve().parent / "_work"
PROSE = (
    "齒輪的方向與速度需要在設計時一併考慮, 錯誤排解時先確認傳動比. 協同設計以 GitHub 倉儲管理, "
    "每位組員在 cd2021 倉儲中撰寫週報. 機構模擬使用 CoppeliaSim 與 pybullet, 馬達以位置控制驅動手臂. "
    "產品簡化後重新繪製 2D 工程圖與 3D 爆炸圖, 並以影片說明組裝流程. "
)
CODE = "```python\nimport sim as vrep\nclientID = vrep.simxStart('127.0.0.1', 19997, True, True, 5000, 5)\nfor i in range(3):\n    print(i * 2)\n```\n"
TABLE = "| 項目 | 數值 | 說明 |\n|---|---|---|\n| 速度 | 2 rad/s | 最大 |\n| 步進 | 0.5 rad/s | 每次 |\n"


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
                body.append(CODE if h == 1 else TABLE)
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


def timed(cmd: list[str], cwd: Path | None = None) -> tuple[float, float]:
    """Run a command; return (seconds, peak resident memory in MB) of that child alone."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _pid, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}\n{proc.stderr.read().decode()[-2000:]}")
    return seconds, usage.ru_maxrss / 1024


def hugo_site(corpus: Path, dest: Path) -> Path:
    """A minimal Hugo project over the same Markdown, with the full menu on every page."""
    if dest.exists():
        shutil.rmtree(dest)
    (dest / "layouts/_default").mkdir(parents=True)
    shutil.copytree(corpus, dest / "content")
    for index in (dest / "content").rglob("index.md"):
        index.rename(index.with_name("_index.md"))
    (dest / "hugo.toml").write_text(
        'baseURL = "http://127.0.0.1/"\ntitle = "bench"\ndisableKinds = ["taxonomy", "term", "RSS"]\n',
        encoding="utf-8",
    )
    menu = (
        '{{ define "tree" }}<ul>{{ range .Sections }}<li><a href="{{ .RelPermalink }}">{{ .Title }}</a>'
        '{{ template "tree" . }}</li>{{ end }}{{ range .RegularPages }}<li><a href="{{ .RelPermalink }}">'
        "{{ .Title }}</a></li>{{ end }}</ul>{{ end }}"
    )
    page = (
        "<!DOCTYPE html><html><head><title>{{ .Title }}</title></head><body><nav>"
        '{{ template "tree" .Site.Home }}</nav><main><h1>{{ .Title }}</h1>{{ .Content }}'
        '{{ with .PrevInSection }}<a href="{{ .RelPermalink }}">{{ .Title }}</a>{{ end }}</main></body></html>'
        + menu
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pages", type=int, default=1000)
    parser.add_argument("--skip-peers", action="store_true")
    args = parser.parse_args()
    corpus = WORK / "corpus"
    files = make_corpus(corpus, args.pages)
    out, cache = WORK / "site", WORK / "cache"
    for d in (out, cache):
        shutil.rmtree(d, ignore_errors=True)
    sitegen = [
        sys.executable,
        "-m",
        "sitegen",
        "build",
        "--source",
        str(corpus),
        "--output",
        str(out),
    ]
    rows: list[tuple[str, float, float]] = []
    rows.append(("sitegen cold", *timed(sitegen)))
    rows.append(("sitegen no-op", *timed(sitegen)))
    edit = files[len(files) // 2]
    edit.write_text(edit.read_text(encoding="utf-8") + "\n一行修改.\n", encoding="utf-8")
    rows.append(("sitegen one-page edit", *timed(sitegen)))
    peers: dict[str, float] = {}
    if not args.skip_peers:
        if shutil.which("hugo"):
            site = hugo_site(corpus, WORK / "hugo")
            secs, mem = timed(["hugo", "--quiet", "-d", str(WORK / "hugo-out")], cwd=site)
            rows.append(("hugo (full menu)", secs, mem))
            peers["hugo"] = secs
        else:
            print("hugo not found: apt-get install hugo", file=sys.stderr)
        try:
            import mkdocs  # noqa: F401

            site = mkdocs_site(corpus, WORK / "mkdocs")
            secs, mem = timed(
                [sys.executable, "-m", "mkdocs", "build", "-q", "-d", str(WORK / "mkdocs-out")],
                cwd=site,
            )
            rows.append(("mkdocs", secs, mem))
            peers["mkdocs"] = secs
        except ImportError:
            print("mkdocs not installed: pip install mkdocs", file=sys.stderr)
    pages = sum(1 for _ in out.rglob("*.html"))
    print(
        f"corpus: {args.pages} Markdown pages, 18 week folders; sitegen wrote {pages} HTML files; {os.cpu_count()} cores"
    )
    print(f"{'run':24} {'seconds':>8} {'peak MB':>8} {'x hugo':>7} {'x mkdocs':>9}")
    for name, secs, mem in rows:
        h = f"{secs / peers['hugo']:.3f}" if "hugo" in peers else "-"
        m = f"{secs / peers['mkdocs']:.3f}" if "mkdocs" in peers else "-"
        print(f"{name:24} {secs:8.2f} {mem:8.0f} {h:>7} {m:>9}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
