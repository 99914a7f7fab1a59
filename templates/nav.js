{#- The whole menu tree for expanding sections in place, loaded on the first expand: a script, not
    JSON, so it loads from file:// too. [title, url, [children]] per page, in menu order. -#}
{%- macro tree(items) %}[{% for i in items %}{% if not loop.first %},{% endif %}[{{ i.title|tojson }},{{ i.url|tojson }},{{ tree(i.children) }}]{% endfor %}]{% endmacro -%}
window.SITEGEN_NAV={{ tree(full_tree) }};
