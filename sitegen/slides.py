"""Slide decks from Markdown pages: the page stays a page, and a deck is published beside it.

A page with ``slides: true`` (or any page but the index under ``slides.dir``) is split into
slides: a line ``---`` starts the next slide, ``--`` a sub-slide below the current one, and a
line starting ``Note:`` begins the speaker notes of the slide. The separators become
``::: slide`` directives line for line (so every link and directive keeps its line number
for diagnostics), the page is rendered as any other, and the deck (``NAME.slides.html``,
beside ``NAME.html``, so every relative link and clip of the page works unchanged) is cut
from the page's finished body at the directives' markers. The viewer is the project's own
``assets/slides.js``: see docs/slides-and-blog.md for why not reveal.js.
"""

from __future__ import annotations

import re
from dataclasses import replace
from html import escape
from pathlib import PurePosixPath
from urllib.parse import quote

from markupsafe import Markup

from sitegen.config import Config
from sitegen.errors import Diagnostics
from sitegen.integrations import Built, Integration
from sitegen.nav import Node, PageInput

_FENCE = re.compile(r"^\s*(`{3,}|~{3,})")
_NEXT = re.compile(r"^---[ \t]*$")
_DOWN = re.compile(r"^--[ \t]*$")
_NOTE = re.compile(r"^Notes?:[ \t]*(.*?)[ \t]*$")
_SPLIT = re.compile(r"<!--slide:(next|down)-->(?:<hr[^>]*>)?")
_NOTES = re.compile(
    r'<!--slide:notes-->(?:<div class="slide-notes" hidden>)?<p class="slide-notes-label">.*?</p>',
    re.S,
)
_NOTES_END = "</div><!--/slide:notes-->"
_DECK_LINK = re.compile(r"<!--slide:deck-->.*?<!--/slide:deck-->", re.S)

LABELS = {
    "en": {
        "slides": "Slides",
        "notes": "Speaker notes",
        "back": "Back to the page",
        "prev": "Previous slide",
        "next": "Next slide",
        "full_short": "Full screen",
        "notes_short": "Notes",
        "print_short": "Print",
        "fullscreen": "Full screen (F)",
        "notes_view": "Notes view (S)",
        "print": "Printable view",
        "help": "Arrows, space, Home/End or swipe to move; F full screen; S notes",
        "below": "more below:",
        "below_label": "Sub-slides below this one (↓)",
        "theme": "Light or dark",
    },
    "zh-TW": {
        "slides": "投影片",
        "notes": "講者備註",
        "back": "回到頁面",
        "prev": "上一張",
        "next": "下一張",
        "full_short": "全螢幕",
        "notes_short": "備註",
        "print_short": "列印",
        "fullscreen": "全螢幕 (F)",
        "notes_view": "備註檢視 (S)",
        "print": "列印檢視",
        "help": "方向鍵、空白鍵、Home/End 或滑動換頁；F 全螢幕；S 備註",
        "below": "下方還有：",
        "below_label": "這張下方還有子投影片 (↓)",
        "theme": "淺色或深色",
    },
}


def deck_url(page_url: str) -> str:
    """``w12/report.html`` -> ``w12/report.slides.html`` (same folder: links stay valid)."""
    return page_url[: -len(".html")] + ".slides.html"


def mark_separators(text: str) -> str:
    """Separators and notes -> ``::: slide`` directive lines, outside code, line for line."""
    out: list[str] = []
    fence = ""
    for line in text.split("\n"):
        m = _FENCE.match(line)
        if m and (not fence or m.group(1).startswith(fence)):
            fence = "" if fence else m.group(1)
            out.append(line)
            continue
        if fence:
            out.append(line)
        elif _NEXT.match(line):
            out.append("::: slide next")
        elif _DOWN.match(line):
            out.append("::: slide down")
        elif note := _NOTE.match(line):
            out.append(f"::: slide notes {note.group(1)}".rstrip())
        else:
            out.append(line)
    return "\n".join(out)


def insert_under_title(text: str, body_line: int, directive: str) -> tuple[str, int]:
    """Put a directive line (the deck link, a post's date) under the page's title without
    moving any other line: into the blank line after a leading ``# Title``, else on a line of
    its own before the text (then the text starts one line earlier in the file's numbering)."""
    lines = text.split("\n")
    first = next((i for i, line in enumerate(lines) if line.strip()), None)
    if (
        first is not None
        and lines[first].startswith("# ")
        and first + 1 < len(lines)
        and not lines[first + 1].strip()
    ):
        lines[first + 1] = directive
        return "\n".join(lines), body_line
    return f"{directive}\n{text}", body_line - 1


def split_deck(body: str, title: str | None) -> list[list[dict]]:
    """A page's finished body -> stacks (horizontal) of slides (vertical) with their notes."""
    body = _DECK_LINK.sub("", body)
    parts = _SPLIT.split(body)
    stacks: list[list[str]] = [[parts[0]]]
    for kind, chunk in zip(parts[1::2], parts[2::2], strict=True):
        if kind == "next":
            stacks.append([chunk])
        else:
            stacks[-1].append(chunk)
    out: list[list[dict]] = []
    for stack in stacks:
        slides = []
        for chunk in stack:
            content, _, notes = chunk.partition("<!--slide:notes-->")
            content = content.strip()
            notes = _NOTES.sub("", "<!--slide:notes-->" + notes if notes else "")
            notes = notes.replace("<!--slide:notes-->", "").replace(_NOTES_END, "").strip()
            notes = re.sub(r'^<p class="slide-notes-label">.*?</p>', "", notes, flags=re.S)
            if content or notes:
                slides.append({"html": Markup(content), "notes": Markup(notes.strip())})
        if slides:
            out.append(slides)
    if title is not None:
        heading = f"<h1>{escape(title)}</h1>"
        if out:
            first = out[0][0]
            first["html"] = Markup(heading + "\n" + str(first["html"]))
        else:
            out = [[{"html": Markup(heading), "notes": Markup("")}]]
    return out or [[{"html": Markup(""), "notes": Markup("")}]]


class SlidesIntegration(Integration):
    """Finds the decks, marks their separators, and publishes one deck file per deck page."""

    def __init__(self, config: Config):
        self.config = config
        self.labels = LABELS.get(config.language, LABELS["en"])
        self.folder = PurePosixPath(config.slides.dir)
        self.decks: list[PurePosixPath] = []

    def is_deck(self, page: PageInput) -> bool:
        if page.body_html is not None:
            return False
        flag = page.meta.get("slides")
        if flag is not None:
            return bool(flag)
        return not page.is_index and page.rel.parts[: len(self.folder.parts)] == self.folder.parts

    def adjust(self, inputs: list[PageInput], diags: Diagnostics) -> list[PageInput]:
        out = []
        for page in inputs:
            if self.is_deck(page):
                marked = mark_separators(page.text)
                if "::: slide notes" in marked:  # a line after the last: no line moves
                    marked = marked.rstrip("\n") + "\n\n::: slide end\n"
                text, first = insert_under_title(marked, page.body_line, "::: slide deck")
                page = replace(page, text=text, body_line=first)
                self.decks.append(page.rel)
            out.append(page)
        return out

    def fingerprint(self) -> str:
        return "slides:" + ",".join(str(r) for r in sorted(self.decks))

    def directives(self) -> dict:
        labels = self.labels
        # Speaker notes are for the presenter: on the page they are a hidden block, opened at
        # `Note:` and closed at the next separator or the page's end (`::: slide end`). A
        # page's directives are expanded in order, each page at once, so the open block is
        # known per page.
        notes_open: set[str] = set()

        def close(node: Node) -> str:
            if node.url in notes_open:
                notes_open.discard(node.url)
                return _NOTES_END
            return ""

        def slide(arg: str, node: Node) -> str:
            kind, _, rest = arg.partition(" ")
            if kind == "next":
                return close(node) + '<!--slide:next--><hr class="slide-break">'
            if kind == "down":
                return close(node) + '<!--slide:down--><hr class="slide-break slide-down">'
            if kind == "end":
                return close(node)
            if kind == "notes":
                extra = _inline(rest, self.config.markdown.raw_html) if rest.strip() else ""
                if node.url in notes_open:
                    return extra
                notes_open.add(node.url)
                label = f'<p class="slide-notes-label">{escape(labels["notes"])}</p>'
                return f'<!--slide:notes--><div class="slide-notes" hidden>{label}{extra}'
            if kind == "deck":
                notes_open.discard(node.url)
                href = quote(deck_url(node.url).rsplit("/", 1)[-1])
                return (
                    f'<!--slide:deck--><p class="slides-link"><a href="{href}">'
                    f"▶ {escape(labels['slides'])}</a></p><!--/slide:deck-->"
                )
            raise LookupError(
                f"unknown slide directive '{kind}' (known: next, down, notes, end, deck)"
            )

        return {"slide": slide}

    def site_files(self, built: Built, diags: Diagnostics) -> dict[str, bytes]:
        from sitegen.links import expand_directives, rewrite_links
        from sitegen.pages import root_prefix

        out: dict[str, bytes] = {}
        for rel in self.decks:
            node = built.site.by_source.get(rel)
            if node is None or node.source is None:
                continue
            src, rendered = node.source, built.renders[node.url]
            file = f"{built.content_name}/{rel}"
            quiet = Diagnostics()  # the page itself reported these already
            body = rewrite_links(
                rendered.html, node, built.targets, quiet, file, src.text, src.body_line
            )
            body = expand_directives(
                body, node, built.handlers, quiet, file, rendered.directives, src.body_line
            )
            stacks = split_deck(body, node.title if node.strip_first_heading else None)
            context = {
                **built.base,
                "root": root_prefix(node.url),
                "title": node.title,
                "page_href": quote(node.url.rsplit("/", 1)[-1]),
                "stacks": stacks,
                "count": sum(len(s) for s in stacks),
                "labels": self.labels,
            }
            out[deck_url(node.url)] = built.theme.render("slides.html", context).encode()
        return out


def _inline(text: str, raw_html: str = "keep") -> str:
    import markdown

    html = markdown.markdown(text, output_format="html")
    if raw_html == "strip":  # as the page's own Markdown (sitegen/html_clean.py)
        from sitegen.html_clean import strip_raw_html

        html = strip_raw_html(html)
    return html
