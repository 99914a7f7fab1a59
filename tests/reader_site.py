"""A small course site as a newcomer has it: ``sitegen new`` (a week page with a clip, the
gallery, a roster) plus what the reader-side tests look at -- a deck with sub-slides and notes,
blog posts, pages holding words that are names of JavaScript's Object.prototype, a YouTube
frame, and a page whose last section is short. Built once per test module."""

from __future__ import annotations

from pathlib import Path

import yaml
from sitegen_helpers import run_cli, write_tree

WORDS = ("constructor", "__proto__", "toString", "hasOwnProperty")

EXTRA = {
    "content/slides/w1-report.md": """---
title: W1 report
---
# W1 report

Group 1

Note: Say who is in the group.

---

## The program

```python
print("hello")
```

--

## Below: the result

The rover turns at the wall.

Note: Show the clip.

--

## Below: problems

None yet.

---

## Thanks
""",
    "content/blog/first.md": "---\ndate: 2024-03-01\ntags: [start]\n---\n# First post\n\n"
    "We set up the **tools** and the `sitegen` site this week, then drove the rover.\n",
    "content/blog/second.md": "---\ndate: 2024-03-08\nsummary: The second week.\n---\n"
    "# Second post\n\nMore text.\n",
    "content/stage-1/video.md": "# A video\n\nThe lecture:\n\n"
    '<iframe width="560" height="315" src="https://www.youtube.com/embed/abc" '
    'title="Lecture video" allowfullscreen></iframe>\n',
    "content/stage-1/long.md": "# Long page\n\n"
    + "".join(f"## Part {i}\n\n" + "Text of this part. " * 80 + "\n\n" for i in range(1, 4))
    + "## Last\n\nShort.\n",
    **{
        f"content/stage-1/word-{i}.md": f"# Word {i}\n\nThis page explains `{w}` in a sentence.\n\n"
        f"## `{w}`\n\nMore about `{w}`.\n"
        for i, w in enumerate(WORDS)
    },
}


def build_reader_site(root: Path) -> Path:
    """The project folder; its site is in ``site/``."""
    made = run_cli("new", str(root), "--language", "en", "--title", "Reader test")
    assert made.returncode == 0, made.stderr
    config = root / "sitegen.yml"
    data = yaml.safe_load(config.read_text(encoding="utf-8"))
    data["sims"].update(size="160x120", fps=10)
    for clip in data["sims"]["clips"]:
        clip.update(seconds=2, speed=1)
    config.write_text(yaml.safe_dump(data, allow_unicode=True), encoding="utf-8")
    write_tree(root, EXTRA)
    built = run_cli("build", "--strict", "--source", str(root))
    assert built.returncode == 0, built.stderr
    return root
