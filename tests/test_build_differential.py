"""An incremental build equals a clean build, byte for byte, after any sequence of edits.

Every shortcut of a partial build (the stat walk, reused input keys, the fragment store, the
spliced search index, reused site-wide files) is a claim that some output cannot have changed.
This test checks all of them at once the way a user would notice a wrong one: random sequences
of the edits an author makes (a page's body, its title, other front matter, its slug, a new
page, a deleted page, a template, sitegen.yml), each followed by an incremental build of the
same output that must equal a build from nothing (fresh output, fresh cache). Hypothesis
shrinks a failure to the shortest sequence that shows it. A code change is the other edit a
build must notice: ``test_code_edit_rebuilds_what_it_changes`` runs builds on a copy of the
package and edits its heading-id code between them.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule
from sitegen_helpers import REPO, run_build, snapshot, write_tree

import sitegen.content

WORDS = ["alpha", "beta", "gamma", "delta", "constructor", "機器人", "week", "clip"]
TEMPLATE = """{% extends "base.html" %}
{% block main %}<p class="marker">MARK</p><h1>{{ page.title }}</h1>{{ page.body }}{% endblock %}
"""


class Edits(RuleBasedStateMachine):
    """A small site and the edits an author makes to it."""

    def __init__(self) -> None:
        super().__init__()
        import tempfile

        self.root = Path(tempfile.mkdtemp(prefix="sitegen-diff-"))
        self.clock = 1_700_000_000 * 10**9  # each write moves the file's mtime forward
        self.pages: dict[str, dict] = {}
        self.serial = 0
        self.builds = 0

    # -- the site -----------------------------------------------------------------------------
    @property
    def src(self) -> Path:
        return self.root / "src"

    def write(self, rel: str, text: str) -> None:
        path = self.src / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        self.clock += 10**9
        os.utime(path, ns=(self.clock, self.clock))

    def page_text(self, page: dict) -> str:
        front = [f"title: {page['title']}"] if page["title"] else []
        if page["slug"]:
            front.append(f"slug: {page['slug']}")
        if page["weight"] is not None:
            front.append(f"weight: {page['weight']}")
        head = "---\n" + "\n".join(front) + "\n---\n" if front else ""
        return f"{head}# {page['heading']}\n\n{page['body']}\n\n## {page['heading']} part\n\nmore\n"

    def save(self, rel: str) -> None:
        self.write(f"content/{rel}", self.page_text(self.pages[rel]))

    @initialize()
    def start(self) -> None:
        self.write("sitegen.yml", "title: Differential\nlanguage: en\n")
        self.write("content/index.md", "# Home\n\nSee [the first page](w1/p0.md).\n")
        for rel in ("w1/index.md", "w1/p0.md", "w1/p1.md", "w2/index.md", "w2/p2.md"):
            self.serial += 1
            self.pages[rel] = {
                "title": f"Start {self.serial}",
                "heading": f"Page {self.serial}",
                "body": "text",
                "slug": None if rel.endswith("index.md") else Path(rel).stem,
                "weight": None,
            }
            self.save(rel)
        self.build()

    # -- building ------------------------------------------------------------------------------
    def build(self) -> None:
        run_build(self.src, self.root / "site", cache_dir=self.root / "cache")
        self.builds += 1

    @invariant()
    def equals_clean_build(self) -> None:
        if not self.builds:
            return
        fresh = self.root / f"clean-{self.builds}"
        run_build(self.src, fresh / "site", cache_dir=fresh / "cache")
        got, want = snapshot(self.root / "site"), snapshot(fresh / "site")
        differ = sorted(k for k in set(got) | set(want) if got.get(k) != want.get(k))
        shutil.rmtree(fresh)
        assert not differ, f"incremental build differs from a clean build in {differ[:8]}"

    def teardown(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)

    # -- the edits -----------------------------------------------------------------------------
    pick = st.integers(min_value=0, max_value=99)

    def chosen(self, i: int) -> str:
        names = sorted(self.pages)
        return names[i % len(names)]

    @rule(i=pick, word=st.sampled_from(WORDS))
    def edit_body(self, i: int, word: str) -> None:
        rel = self.chosen(i)
        self.pages[rel]["body"] += f" {word}"
        self.save(rel)
        self.build()

    @rule(i=pick, word=st.sampled_from(WORDS))
    def edit_title(self, i: int, word: str) -> None:
        rel = self.chosen(i)
        self.pages[rel]["title"] = f"Title {word} {self.serial}"
        self.serial += 1
        self.save(rel)
        self.build()

    @rule(i=pick, word=st.sampled_from(WORDS))
    def edit_heading(self, i: int, word: str) -> None:
        rel = self.chosen(i)
        self.pages[rel]["heading"] = f"Heading {word}"
        self.save(rel)
        self.build()

    @rule(i=pick, weight=st.one_of(st.none(), st.integers(min_value=-3, max_value=3)))
    def edit_weight(self, i: int, weight: int | None) -> None:
        rel = self.chosen(i)
        self.pages[rel]["weight"] = weight
        self.save(rel)
        self.build()

    @rule(i=pick, slug=st.sampled_from([None, "fixed", "other-name", "p"]))
    def edit_slug(self, i: int, slug: str | None) -> None:
        rel = self.chosen(i)
        self.pages[rel]["slug"] = slug
        self.save(rel)
        self.build()

    @rule(folder=st.sampled_from(["w1", "w2", "w3"]), word=st.sampled_from(WORDS))
    def new_page(self, folder: str, word: str) -> None:
        self.serial += 1
        rel = f"{folder}/n{self.serial}.md"
        self.pages[rel] = {
            "title": None,
            "heading": f"New {word}",
            "body": word,
            "slug": None,
            "weight": None,
        }
        self.save(rel)
        self.build()

    @rule(i=pick)
    def delete_page(self, i: int) -> None:
        rel = self.chosen(i)
        if len(self.pages) <= 1 or rel.endswith("index.md"):
            return
        del self.pages[rel]
        (self.src / "content" / rel).unlink()
        self.build()

    @rule(mark=st.sampled_from(["one", "two", None]))
    def edit_template(self, mark: str | None) -> None:
        path = self.src / "templates" / "page.html"
        if mark is None:
            if path.exists():
                path.unlink()
        else:
            self.write("templates/page.html", TEMPLATE.replace("MARK", mark))
        self.build()

    @rule(title=st.sampled_from(["Differential", "Another title", "課程"]))
    def edit_config(self, title: str) -> None:
        self.write("sitegen.yml", f"title: {title}\nlanguage: en\n")
        self.build()


@pytest.fixture(autouse=True)
def _settled(monkeypatch):
    """Files count as settled at once (each write moves its mtime a second on): the stat
    shortcuts are the ones under test."""
    monkeypatch.setattr(sitegen.content, "RACY_NS", 0)


TestEdits = Edits.TestCase
TestEdits.settings = settings(
    max_examples=8,
    stateful_step_count=8,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)


def _copy_packages(dest: Path) -> Path:
    """This checkout's packages (and theme) in a folder of their own, to be edited."""
    for name in ("located", "roster", "sims", "sitegen"):
        shutil.copytree(
            REPO / name, dest / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc")
        )
    theme = shutil.copytree(REPO / "templates", dest / "sitegen" / "_theme")
    (theme / "__init__.py").touch()  # as installed: the theme is a package of its own
    return dest


def _build_with(code: Path, src: Path, out: Path, memo: Path) -> None:
    env = {
        **os.environ,
        "PYTHONPATH": str(code),
        "SITEGEN_CODE_MEMO": str(memo),
        "SITEGEN_JOBS": "1",
    }
    run = subprocess.run(
        [sys.executable, "-m", "sitegen", "build", "--source", str(src), "--output", str(out)],
        capture_output=True,
        text=True,
        env=env,
        cwd=code,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr


def test_code_edit_rebuilds_what_it_changes(tmp_path: Path) -> None:
    """The Markdown cache is keyed by the code that renders: an edit of the heading-id code
    (sitegen/slugs.py, imported by the renderer) gives the new ids at the next build, equal to
    a clean build, with no hand-bumped version."""
    code = _copy_packages(tmp_path / "code")
    src = write_tree(
        tmp_path / "src",
        {"sitegen.yml": "title: Code\n", "content/index.md": "# Home\n\n## A Part\n\ntext\n"},
    )
    out, memo = tmp_path / "site", tmp_path / "memo.json"
    _build_with(code, src, out, memo)
    assert 'id="a-part"' in (out / "index.html").read_text(encoding="utf-8")
    slugs = code / "sitegen" / "slugs.py"
    text = slugs.read_text(encoding="utf-8")
    assert "def heading_id(" in text
    slugs.write_text(
        text + "\n\n_heading_id = heading_id\n\n\ndef heading_id(*a, **k):\n"
        "    return 'h-' + _heading_id(*a, **k)\n",
        encoding="utf-8",
    )
    _build_with(code, src, out, memo)
    page = (out / "index.html").read_text(encoding="utf-8")
    assert 'id="h-a-part"' in page, "the build served heading ids from before the code edit"
    fresh = shutil.copytree(src, tmp_path / "fresh", ignore=shutil.ignore_patterns(".sitegen-*"))
    _build_with(code, fresh, tmp_path / "clean", memo)
    assert snapshot(out) == snapshot(tmp_path / "clean")
