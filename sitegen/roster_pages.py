"""Rosters in the site: one generated page per configured roster, a JSON export, the
``::: roster NAME`` directive, and a report of what changed since the last build.

Teachers regenerate the site after editing a roster; the change report (members added,
removed, moved, accounts changed) is how they see that the edit did what they meant.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path, PurePosixPath

from roster import RosterError, diff, load_roster
from roster.emit import html_view, to_json
from sitegen.config import Config, RosterConfig
from sitegen.errors import Diagnostics
from sitegen.i18n import roster_labels
from sitegen.integrations import Integration
from sitegen.links import url_quote
from sitegen.nav import Node, PageInput
from sitegen.output import OutFile, from_bytes
from sitegen.pages import root_prefix
from sitegen.partials import Partials


def _read(path) -> bytes:
    try:
        return path.read_bytes()
    except OSError:
        return b""


class RosterIntegration(Integration):
    def __init__(self, config: Config):
        self.config = config
        self.results: dict[str, object] = {}
        self.labels: dict[str, str] | None = None  # the site's words, set by pages()
        self.state_before: dict = {}
        self.partials = Partials(config)

    def fingerprint(self) -> str:
        h = hashlib.sha256(self.config.course_repo.encode())
        for r in self.config.rosters:
            h.update(repr(r).encode())
            h.update(_read(r.file))
            if r.corrections:
                h.update(_read(r.corrections))
            if r.aliases:
                h.update(_read(r.aliases))
        return "roster:" + h.hexdigest()

    def _rel(self, path) -> str:
        try:
            return str(path.relative_to(self.config.root))
        except ValueError:
            return str(path)

    def prepare(self, diags: Diagnostics, state) -> None:
        self.state_before = dict(state.rosters)
        for rc in self.config.rosters:
            missing = [
                (what, path)
                for what, path in (("corrections", rc.corrections), ("aliases", rc.aliases))
                if path is not None and not path.is_file()
            ]
            for what, path in missing:
                diags.error(self._rel(path), None, f"rosters[{rc.name}].{what}", "file not found")
            if missing:
                continue
            try:
                result = load_roster(
                    rc.file,
                    corrections=rc.corrections,
                    course_repo=self.config.course_repo,
                    layout=rc.layout,
                    aliases=rc.aliases,
                )
            except RosterError as exc:
                diags.add(replace(exc.diagnostic, file=self._rel(Path(exc.file))))
                continue
            for d in result.diagnostics:
                if d.severity != "info":  # roster and site share one Diagnostic type
                    diags.add(replace(d, file=self._rel(Path(d.file))))
            if result.ok:
                self.results[rc.name] = result

    def _page_rel(self, rc: RosterConfig) -> PurePosixPath:
        section = rc.section.strip("/")
        return (
            PurePosixPath(section, f"{rc.name}.md") if section else PurePosixPath(f"{rc.name}.md")
        )

    def pages(self, strings: dict[str, str]) -> list[PageInput]:
        self.labels = roster_labels(strings)
        out = []
        for rc in self.config.rosters:
            result = self.results.get(rc.name)
            if result is None:
                continue
            rel = self._page_rel(rc)
            depth = len(rel.parts) - 1
            json_href = "../" * depth + url_quote(f"roster/{rc.name}.json")
            body = self._html(result, json_href, strings["roster_json"])
            toc = [
                {"id": f"group-{g.slug}", "title": g.name, "children": []}
                for g in result.roster.groups
            ]
            out.append(
                PageInput(
                    rel,
                    {"title": rc.title, "weight": rc.weight},
                    "",
                    False,
                    None,
                    rc.name,
                    body_html=body,
                    toc=toc,
                    digest=hashlib.sha256(body.encode()).hexdigest(),
                )
            )
        return out

    def _html(self, result, json_href: str, json_label: str) -> str:
        """A roster's HTML from the theme's ``partials/roster.html``, after its JSON link."""
        view = html_view(result, self.labels)
        return self.partials.render(
            "roster", roster=view, json_href=json_href, json_label=json_label
        )

    def files(self) -> dict[str, OutFile]:
        return {
            f"roster/{name}.json": from_bytes(to_json(r).encode())
            for name, r in sorted(self.results.items())
        }

    def directives(self) -> dict:
        def roster_directive(arg: str, node: Node) -> str:
            result = self.results.get(arg.strip())
            if result is None:
                known = ", ".join(sorted(self.results)) or "none configured"
                raise LookupError(f"no roster named '{arg}' (known: {known})")
            href = root_prefix(node.url) + url_quote(f"roster/{arg.strip()}.json")
            return self._html(result, href, "JSON")

        return {"roster": roster_directive}

    def notes(self, state) -> list[str]:
        lines = []
        for name, result in sorted(self.results.items()):
            old = self.state_before.get(name)
            if old is None:
                continue
            for change in diff(old, result.to_dict()):
                lines.append(f"roster {name}: {change}")
        return lines

    def save(self, state) -> None:
        state.rosters = {name: r.to_dict() for name, r in sorted(self.results.items())}
