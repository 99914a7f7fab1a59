"""``markdown: {raw_html: strip}``: what a page's Markdown may put in the site when its authors
are not trusted (a site that takes pages from students or from pull requests).

Markdown passes raw HTML through: a page can hold ``<script>``, ``<iframe>``, ``onclick=``
handlers, ``javascript:`` links (``[x](javascript:...)``), or attributes added by ``{...}``
(attr_list). With ``raw_html: strip`` each page's HTML fragment is cleaned, right after
Markdown made it, with nh3 (the Python binding of the Rust sanitizer ammonia, kept for exactly
this): only the elements and attributes Markdown and its extensions write here, plus plain
text markup authors commonly use, stay; links and sources keep only ``http``, ``https`` and
``mailto`` URLs or relative ones; ``<script>`` and ``<style>`` go with their content; inline
styles keep ``text-align`` only (tables); ``data-*`` attributes go (the theme's scripts act on
some). Comments stay: they carry the ``::: clip`` directives. Directives (clips, rosters) and
everything the theme adds are the site's own and are not cleaned.

Why a library: parsing HTML the way browsers do is what makes such a filter hold; a few regular
expressions would not.
"""

from __future__ import annotations

MODES = ("keep", "strip")

TAGS = {
    # what Markdown and the extensions used here write
    "a", "abbr", "blockquote", "br", "code", "dd", "del", "details", "div", "dl", "dt", "em",
    "h1", "h2", "h3", "h4", "h5", "h6", "hr", "img", "input", "label", "li", "ol", "p", "pre",
    "span", "strong", "summary", "sup", "sub", "table", "tbody", "td", "tfoot", "th", "thead",
    "tr", "ul",
    # plain text markup authors write by hand
    "b", "i", "u", "s", "small", "mark", "kbd", "samp", "var", "q", "cite", "dfn", "time", "ins",
    "figure", "figcaption", "caption", "colgroup", "col", "ruby", "rt", "rp",
    "video", "audio", "source", "track",
}  # fmt: skip
ATTRIBUTES = {
    "*": {"class", "id", "title", "lang", "dir"},
    "a": {"href", "name"},
    "img": {"src", "alt", "width", "height", "loading"},
    "input": {"type", "name", "checked", "disabled"},
    "label": {"for"},
    "ol": {"start", "reversed", "type"},
    "td": {"colspan", "rowspan", "style"},
    "th": {"colspan", "rowspan", "style", "scope"},
    "col": {"span"},
    "colgroup": {"span"},
    "details": {"open"},
    "time": {"datetime"},
    "video": {"src", "controls", "width", "height", "poster", "loop", "muted", "playsinline"},
    "audio": {"src", "controls", "loop", "muted"},
    "source": {"src", "type"},
    "track": {"src", "kind", "srclang", "label", "default"},
}
INPUT_TYPES = {"radio", "checkbox"}  # content tabs; task lists
URL_SCHEMES = {"http", "https", "mailto"}


def strip_raw_html(fragment: str) -> str:
    """``fragment`` with everything outside the lists above removed."""
    import nh3

    return nh3.clean(
        fragment,
        tags=TAGS,
        clean_content_tags={"script", "style"},
        attributes=ATTRIBUTES,
        attribute_filter=_attribute,
        strip_comments=False,
        link_rel=None,
        url_schemes=URL_SCHEMES,
        filter_style_properties={"text-align"},
    )


def _attribute(tag: str, name: str, value: str) -> str | None:
    if tag == "input" and name == "type" and value.lower() not in INPUT_TYPES:
        return None
    return value
