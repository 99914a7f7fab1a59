"""The theme environment's direct dict look-ups render exactly what Jinja2's own do.

Checked against a stock ``jinja2.Environment`` with the same settings: attributes that are
keys, keys named like dict methods, missing keys (an error with StrictUndefined, as before),
other mappings and objects, and the default theme's page template.
"""

from __future__ import annotations

from collections import OrderedDict
from types import SimpleNamespace
from urllib.parse import quote

import jinja2
import pytest
from markupsafe import Markup

from sitegen.theme import Theme, default_theme_dir
from sitegen.theme_env import ThemeEnvironment

TEMPLATE = (
    "{{ d.title }}|{{ d.items is defined }}|{{ d['items'] }}|{{ d.keys is callable }}|"
    "{{ d.nested.x }}|{{ d.get('title') }}|{{ o.name }}|{{ od.title }}|{{ d.html }}|"
    "{% for k, v in d.items() %}{{ k }}={{ v }};{% endfor %}|{{ d.title|length }}"
)
CONTEXT = {
    "d": {
        "title": "齒輪 <b>",
        "items": "a key named items",
        "nested": {"x": 1},
        "html": Markup("<i>"),
    },
    "o": SimpleNamespace(name="object & attribute"),
    "od": OrderedDict(title="an OrderedDict"),
}


def _envs(**options):
    return (
        jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined, **options),
        ThemeEnvironment(autoescape=True, undefined=jinja2.StrictUndefined, **options),
    )


def test_attribute_lookups_render_as_with_stock_jinja():
    stock, ours = _envs()
    assert ours.from_string(TEMPLATE).render(CONTEXT) == stock.from_string(TEMPLATE).render(CONTEXT)
    assert "a key named items" in ours.from_string(TEMPLATE).render(CONTEXT)


@pytest.mark.parametrize("expr", ["d.missing", "d.nested.missing", "o.missing"])
def test_a_missing_key_is_still_an_error(expr):
    for env in _envs():
        with pytest.raises(jinja2.UndefinedError):
            env.from_string("{{ " + expr + " }}").render(CONTEXT)


def test_default_page_template_renders_as_with_stock_jinja():
    loader = jinja2.FileSystemLoader([str(default_theme_dir())])
    stock, ours = _envs(loader=loader, keep_trailing_newline=True)
    for env in (stock, ours):
        env.filters["u"] = lambda path: str(path)
    theme_env = Theme(None).env
    assert isinstance(theme_env, ThemeEnvironment)
    for path in ("stage-1/w1/第 1 週.html", "a b/c#d?e.html", "x.html"):  # twice: cached
        expected = quote(path, safe="/#-._~!$&'()*+,;=:@%")
        assert theme_env.filters["u"](path) == theme_env.filters["u"](path) == expected
    page = {
        "title": "第 1 週",
        "url": "stage-1/w1/index.html",
        "breadcrumbs": [{"title": "Stage 1", "url": "stage-1/index.html"}],
        "toc": [{"id": "a", "title": "A", "children": [{"id": "b", "title": "B"}]}],
        "body": Markup("<p>body</p>"),
        "children": [{"title": "child", "url": "stage-1/w1/c.html"}],
        "prev": {"title": "prev", "url": "stage-1/index.html"},
        "next": None,
    }
    keys = "copy_code copied_code results no_results all_results skip close_menu menu "
    keys += "search_placeholder search site_map theme close_hint built_with breadcrumb "
    keys += "on_this_page in_this_section previous next pager_top pager_bottom"
    context = {
        "site": {"language": "zh-TW", "title": "課程", "description": "", "author": "cd"},
        "t": {k: k.replace("_", " ") for k in keys.split()},
        "root": "../",
        "build_date": "",
        "menu_html": Markup("<ul></ul>"),
        "page": page,
    }
    html = ours.get_template("page.html").render(context)
    assert html == stock.get_template("page.html").render(context)
    assert "第 1 週" in html and 'href="#b"' in html
