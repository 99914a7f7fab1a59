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


def _member_html(
    result: RosterResult, leader_id: str, m: Member, labels: dict | None = None
) -> str:
    """One `<li>`: id (struck through when a mark says so), marks with their meaning, links."""
    lb = {**LABELS, **(labels or {})}
    rules = result.marks_of(m)
    leader = (
        f' <span class="roster-leader">({escape(lb["leader"])})</span>' if m.id == leader_id else ""
    )
    marks = "".join(
        f' <span class="roster-mark"{_title(r.meaning)}>{escape(r.word, quote=True)}</span>'
        for r in rules
    )
    notes = "".join(f' <span class="roster-note">{escape(n, quote=True)}</span>' for n in m.notes)
    sid = f'<span class="roster-id">{escape(m.id, quote=True)}</span>'
    if any(r.strike for r in rules):
        sid = f"<s>{sid}</s>"
    if result.linked(m):
        m_repo, m_site = m.urls(result.course_repo)
        links = (
            f"{_link(m_repo, m.id + ' ' + lb['repo'])} | {_link(m_site, m.id + ' ' + lb['site'])}"
        )
    else:
        why = "; ".join(r.meaning for r in rules if not r.links and r.meaning)
        links = '<span class="roster-unlinked">not linked' + (
            f" ({escape(why, quote=True)})</span>" if why else "</span>"
        )
    cls = ' class="roster-marked"' if rules else ""
    return f"<li{cls}>{sid}{leader}{marks}{notes}: {links}</li>"


def _title(text: str) -> str:
    return f' title="{escape(text, quote=True)}"' if text else ""


# Words in the HTML; sitegen passes its interface strings (zh-TW or en) in their place.
LABELS = {
    "summary": "",  # "" = English with plurals; else "{groups} ... {members} ..."
    "member_count": "",  # "" = English with plurals; else "{n} ..."
    "leader": "leader",
    "repo": "repo",
    "site": "site",
}


def to_html(result: RosterResult, labels: dict | None = None) -> str:
    """An HTML fragment: a summary, then one `<section id="group-<slug>">` per group.

    Each section has the group repo and site links (owned by the leader), then
    one line per member with the id and the member's repo and site links -- the
    same link set the course's `task1_roster_links.py` printed.
    """
    groups = result.roster.groups
    n_members = sum(len(g.members) for g in groups)
    lb = {**LABELS, **(labels or {})}
    summary = (
        lb["summary"].format(groups=len(groups), members=n_members)
        if lb["summary"]
        else f"{_plural(len(groups), 'group')}, {_plural(n_members, 'member')}"
    )
    parts = ['<div class="roster">', f'<p class="roster-summary">{escape(summary)}</p>']
    for group in groups:
        g_repo, g_site = group.urls()
        name = escape(group.name, quote=True)
        parts.append(f'<section class="roster-group" id="group-{escape(group.slug, quote=True)}">')
        parts.append(f"<h3>{name}</h3>")
        n = len(group.members)
        count = lb["member_count"].format(n=n) if lb["member_count"] else _plural(n, "member")
        parts.append(
            f'<p class="roster-group-links">{_link(g_repo, group.name + " " + lb["repo"])} | '
            f"{_link(g_site, group.name + ' ' + lb['site'])} "
            f'<span class="roster-count">({escape(count)})</span></p>'
        )
        parts.append('<ul class="roster-members">')
        for m in group.members:
            parts.append(_member_html(result, group.leader, m, labels))
        parts.append("</ul>")
        parts.append("</section>")
    parts.append("</div>")
    return "\n".join(parts) + "\n"
