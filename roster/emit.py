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

from .links import group_urls, member_urls
from .model import RosterResult

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
        g_repo, g_site = group_urls(group)
        for m in group.members:
            m_repo, m_site = member_urls(m, result.course_repo)
            writer.writerow(
                [
                    _cell(group.name),
                    m.id,
                    m.account,
                    "yes" if m.id == group.leader else "",
                    _cell("; ".join(m.notes)),
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


def to_html(result: RosterResult) -> str:
    """An HTML fragment: a summary, then one `<section id="group-<slug>">` per group.

    Each section has the group repo and site links (owned by the leader), then
    one line per member with the id and the member's repo and site links -- the
    same link set the course's `task1_roster_links.py` printed.
    """
    groups = result.roster.groups
    n_members = sum(len(g.members) for g in groups)
    parts = [
        '<div class="roster">',
        f'<p class="roster-summary">{_plural(len(groups), "group")}, {_plural(n_members, "member")}</p>',
    ]
    for group in groups:
        g_repo, g_site = group_urls(group)
        name = escape(group.name, quote=True)
        parts.append(f'<section class="roster-group" id="group-{escape(group.slug, quote=True)}">')
        parts.append(f"<h3>{name}</h3>")
        parts.append(
            f'<p class="roster-group-links">{_link(g_repo, group.name + " repo")} | '
            f"{_link(g_site, group.name + ' site')} "
            f'<span class="roster-count">({_plural(len(group.members), "member")})</span></p>'
        )
        parts.append('<ul class="roster-members">')
        for m in group.members:
            m_repo, m_site = member_urls(m, result.course_repo)
            leader = ' <span class="roster-leader">(leader)</span>' if m.id == group.leader else ""
            notes = "".join(
                f' <span class="roster-note">{escape(n, quote=True)}</span>' for n in m.notes
            )
            parts.append(
                f'<li><span class="roster-id">{escape(m.id, quote=True)}</span>{leader}{notes}: '
                f"{_link(m_repo, m.id + ' repo')} | {_link(m_site, m.id + ' site')}</li>"
            )
        parts.append("</ul>")
        parts.append("</section>")
    parts.append("</div>")
    return "\n".join(parts) + "\n"
