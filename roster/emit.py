"""Output formats: JSON (for machines and diffs), CSV (for spreadsheets), HTML (for the site).

All three are deterministic for the same roster, so regenerated files only
change when the roster does. HTML escapes every value, including attribute
values, even though validation already restricts accounts and slugs: the
escaping is what keeps the page safe if validation is ever loosened.
"""

from __future__ import annotations

import csv
import io
import json
from html import escape

from .model import Member, RosterResult

CSV_COLUMNS = [
    "group",
    "id",
    "account",
    "leader",
    "notes",
    "repo_url",
    "site_url",
    "group_repo_url",
    "group_site_url",
]
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def to_json(result: RosterResult) -> str:
    """`result.to_dict()` as sorted, indented JSON with a trailing newline."""
    return json.dumps(result.to_dict(), sort_keys=True, indent=2, ensure_ascii=False) + "\n"


def _cell(value: str) -> str:
    """Neutralise spreadsheet formulas in free-text cells (CSV injection)."""
    return "'" + value if value.startswith(_FORMULA_START) else value


def to_csv(result: RosterResult) -> str:
    """One row per member with group and member links; readable back by `load_roster`."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for group in result.roster.groups:
        g_repo, g_site = group.urls()
        for m in group.members:
            m_repo, m_site = result.member_links(m)
            writer.writerow(
                [
                    _cell(group.name),
                    m.id,
                    m.account,
                    "yes" if m.id == group.leader else "",
                    _cell("; ".join([*m.marks, *m.notes])),
                    m_repo or "",
                    m_site or "",
                    g_repo or "",
                    g_site or "",
                ]
            )
    return out.getvalue()


def _link(url: str | None, text: str) -> str:
    """An escaped link, or escaped plain text marked as unlinked when there is no safe URL."""
    if url is None:
        return f'<span class="roster-nolink">{escape(text, quote=True)}</span>'
    return f'<a href="{escape(url, quote=True)}">{escape(text, quote=True)}</a>'


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


# Words in the HTML; sitegen passes its interface strings (zh-TW or en) in their place.
LABELS = {
    "summary": "",  # "" = English with plurals; else "{groups} ... {members} ..."
    "member_count": "",  # "" = English with plurals; else "{n} ..."
    "leader": "leader",
    "repo": "repo",
    "site": "site",
}


def html_view(result: RosterResult, labels: dict | None = None) -> dict:
    """What the HTML shows, as plain data: the one place that decides the words, which links a
    member gets and why one gets none. :func:`to_html` writes it for the command line; the
    site's theme writes it with ``templates/partials/roster.html``, which a project may override.
    Values are unescaped text; the writers escape them."""
    lb = {**LABELS, **(labels or {})}
    groups = result.roster.groups
    n_members = sum(len(g.members) for g in groups)
    summary = (
        lb["summary"].format(groups=len(groups), members=n_members)
        if lb["summary"]
        else f"{_plural(len(groups), 'group')}, {_plural(n_members, 'member')}"
    )
    out_groups = []
    for group in groups:
        g_repo, g_site = group.urls()
        n = len(group.members)
        out_groups.append(
            {
                "name": group.name,
                "slug": group.slug,
                "repo": {"url": g_repo, "text": f"{group.name} {lb['repo']}"},
                "site": {"url": g_site, "text": f"{group.name} {lb['site']}"},
                "count": lb["member_count"].format(n=n)
                if lb["member_count"]
                else _plural(n, "member"),
                "members": [_member_view(result, group.leader, m, lb) for m in group.members],
            }
        )
    return {"summary": summary, "leader": lb["leader"], "groups": out_groups}


def _member_view(result: RosterResult, leader_id: str, m: Member, lb: dict) -> dict:
    """One member: id (struck through when a mark says so), marks with their meaning, links."""
    rules = result.marks_of(m)
    links = None
    if result.linked(m):
        m_repo, m_site = m.urls(result.course_repo)
        links = [
            {"url": m_repo, "text": f"{m.id} {lb['repo']}"},
            {"url": m_site, "text": f"{m.id} {lb['site']}"},
        ]
    return {
        "id": m.id,
        "leader": m.id == leader_id,
        "marks": [{"word": r.word, "meaning": r.meaning} for r in rules],
        "notes": list(m.notes),
        "strike": any(r.strike for r in rules),
        "links": links,
        "unlinked_why": "; ".join(r.meaning for r in rules if not r.links and r.meaning),
    }


def _member_html(member: dict, leader_word: str) -> str:
    leader = (
        f' <span class="roster-leader">({escape(leader_word)})</span>' if member["leader"] else ""
    )
    marks = "".join(
        f' <span class="roster-mark"{_title(mk["meaning"])}>{escape(mk["word"], quote=True)}</span>'
        for mk in member["marks"]
    )
    notes = "".join(
        f' <span class="roster-note">{escape(n, quote=True)}</span>' for n in member["notes"]
    )
    sid = f'<span class="roster-id">{escape(member["id"], quote=True)}</span>'
    if member["strike"]:
        sid = f"<s>{sid}</s>"
    if member["links"] is not None:
        links = " | ".join(_link(x["url"], x["text"]) for x in member["links"])
    else:
        why = member["unlinked_why"]
        links = '<span class="roster-unlinked">not linked' + (
            f" ({escape(why, quote=True)})</span>" if why else "</span>"
        )
    cls = ' class="roster-marked"' if member["marks"] else ""
    return f"<li{cls}>{sid}{leader}{marks}{notes}: {links}</li>"


def _title(text: str) -> str:
    return f' title="{escape(text, quote=True)}"' if text else ""


def to_html(result: RosterResult, labels: dict | None = None) -> str:
    """An HTML fragment: a summary, then one `<section id="group-<slug>">` per group.

    Each section has the group repo and site links (owned by the leader), then
    one line per member with the id and the member's repo and site links -- the
    same link set the course's `task1_roster_links.py` printed. The site renders the same
    :func:`html_view` with its theme's ``partials/roster.html`` (a test keeps the two alike).
    """
    view = html_view(result, labels)
    parts = ['<div class="roster">', f'<p class="roster-summary">{escape(view["summary"])}</p>']
    for group in view["groups"]:
        parts.append(
            f'<section class="roster-group" id="group-{escape(group["slug"], quote=True)}">'
        )
        parts.append(f"<h3>{escape(group['name'], quote=True)}</h3>")
        parts.append(
            f'<p class="roster-group-links">{_link(group["repo"]["url"], group["repo"]["text"])} | '
            f"{_link(group['site']['url'], group['site']['text'])} "
            f'<span class="roster-count">({escape(group["count"])})</span></p>'
        )
        parts.append('<ul class="roster-members">')
        for m in group["members"]:
            parts.append(_member_html(m, view["leader"]))
        parts.append("</ul>")
        parts.append("</section>")
    parts.append("</div>")
    return "\n".join(parts) + "\n"
