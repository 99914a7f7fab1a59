"""Does a page's conversion cost grow linearly with its size? Stock Python-Markdown vs sitegen's.

Run: ``python bench/markdown_scaling.py [--sizes 100 400]``. For each kind of content, one
page of each size (KB) is converted in a fresh process and its CPU seconds printed; four times
the size should cost about four times as much. "stock" is Python-Markdown with the extensions
sitegen used before its linear-time replacements (sitegen/markdown_speed.py).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

KINDS = {
    "footnotes": "text[^{n}]\n\n[^{n}]: note\n\n",
    "headings + paragraphs": "## Heading {n}\n\ntext {n}\n\n",
    "list items": "- item {n}\n\n",
    "tables": "| a | b |\n|---|---|\n| {n} | 2 |\n\n",
    "raw HTML blocks": "<div>block {n}</div>\n\n",
}


def page(kind: str, kb: int) -> str:
    parts, n, total = [], 0, 0
    while total < kb * 1024:
        piece = KINDS[kind].replace("{n}", str(n))
        parts.append(piece)
        total += len(piece)
        n += 1
    return "".join(parts)


def stock():
    import markdown

    return markdown.Markdown(
        extensions=["tables", "fenced_code", "footnotes", "attr_list", "def_list"]
        + ["sane_lists", "md_in_html", "codehilite", "toc"],
        extension_configs={"codehilite": {"guess_lang": False}, "toc": {"permalink": "#"}},
        output_format="html",
    )


def one(kind: str, which: str, kb: int) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    text = page(kind, kb)
    if which == "stock":
        md = stock()
        start = time.process_time()
        md.convert(text)
    else:
        from sitegen.markdown_render import MarkdownRenderer

        renderer = MarkdownRenderer()
        start = time.process_time()
        renderer.render(text)
    print(f"{time.process_time() - start:.2f}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 400])
    parser.add_argument("--one", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        one(args.one[0], args.one[1], int(args.one[2]))
        return 0
    print(
        "page made of | "
        + " | ".join(f"{w} {kb} KB" for w in ("stock", "sitegen") for kb in args.sizes)
    )
    for kind in KINDS:
        cells = []
        for which in ("stock", "sitegen"):
            for kb in args.sizes:
                cmd = [sys.executable, __file__, "--one", kind, which, str(kb)]
                out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
                cells.append(f"{out.strip()} s")
        print(f"{kind} | " + " | ".join(cells), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
