"""Roster HTML in the site comes from the theme (``partials/roster.html``): by default exactly
what ``sitegen roster links --format html`` prints, and a project's template replaces it."""

from __future__ import annotations

from pathlib import Path

import pytest
from sitegen_helpers import run_build, write_tree

from roster import load_roster
from roster.emit import html_view, to_html
from sitegen.config import Config
from sitegen.i18n import roster_labels, strings
from sitegen.partials import Partials

FIXTURES = Path(__file__).parent / "fixtures" / "roster"
ROSTER = (
    "groups:\n- name: 'g-1'\n  members:\n"
    "  - {id: '40823101', account: '40823101', notes: ['<script>alert(\"x\")</script>']}\n"
    "  - {id: '40823102', account: '40823102', notes: [\"it's & co\"]}\n"
)


def same_entities(html: str) -> str:
    """Jinja writes quotes as &#34;/&#39;, Python's html.escape as &quot;/&#x27;: same text."""
    return html.replace("&#34;", "&quot;").replace("&#39;", "&#x27;")


@pytest.mark.parametrize("name", ["marked.txt", "messy.txt", "small.yml", "ids_only.txt"])
@pytest.mark.parametrize("language", ["en", "zh-TW"])
def test_default_partial_writes_what_the_cli_prints(name, language):
    result = load_roster(FIXTURES / name, course_repo="cd2021")
    labels = roster_labels(strings(language))
    site = Partials(Config(root=FIXTURES)).render(
        "roster", roster=html_view(result, labels), json_href="r.json", json_label="JSON"
    )
    head = '<p><a class="roster-json" href="r.json" download>JSON</a></p>\n'
    assert same_entities(site) == head + to_html(result, labels)
    assert site.count("<li") == sum(len(g.members) for g in result.roster.groups)


def project(root: Path, partial: str | None = None) -> Path:
    files = {
        "sitegen.yml": "title: t\nrosters:\n  - {name: r, title: Groups, file: r.yml}\n",
        "r.yml": ROSTER,
        "content/index.md": "# Home\n\n::: roster r\n",
    }
    if partial is not None:
        files["templates/partials/roster.html"] = partial
    return write_tree(root, files)


def test_roster_page_escapes_every_value(tmp_path):
    out = tmp_path / "o"
    run_build(project(tmp_path / "p"), out)
    page = (out / "groups.html").read_text(encoding="utf-8")
    assert "<script>alert" not in page and "&lt;script&gt;alert(&#34;x&#34;)" in page
    assert "it&#39;s &amp; co" in page and "<h3>g-1</h3>" in page


def test_project_partial_overrides_the_roster_markup(tmp_path):
    partial = (
        '<table class="mine">{% for g in roster.groups %}{% for m in g.members %}'
        "<tr><td>{{ g.name }}</td><td>{{ m.id }}</td>"
        '<td><a href="{{ m.links[0].url }}">{{ m.links[0].text }}</a></td></tr>'
        '{% endfor %}{% endfor %}</table><a href="{{ json_href }}">{{ json_label }}</a>'
    )
    out = tmp_path / "o"
    run_build(project(tmp_path / "p", partial), out)
    for rel, json_href in (("groups.html", "roster/r.json"), ("index.html", "roster/r.json")):
        page = (out / rel).read_text(encoding="utf-8")
        assert '<table class="mine"><tr><td>g-1</td><td>40823101</td>' in page
        assert '<a href="https://github.com/40823101/cd2021">40823101 repo</a>' in page
        assert f'<a href="{json_href}">' in page
        assert 'class="roster-members"' not in page  # the default markup is gone
