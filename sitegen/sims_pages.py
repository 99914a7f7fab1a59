"""Simulation clips in the site: render (or reuse) the configured clips, publish their files,
add the gallery page and the ``::: clip NAME`` directive.

Rendering is delegated to :func:`sims.clips.render_clips`, which caches by content hash and
splits the work across cores; progress is shown by :mod:`sitegen.progress`. A clip never takes
the site down: one that fails is a warning naming it and its cause (an error under
``--strict``), its previous good render is shown marked stale, and without one its page and
gallery entry show a placeholder with the error. The failure is remembered in the clip cache;
``--retry-failed`` renders it again. See docs/clips.md.
"""

from __future__ import annotations

import hashlib
import json
from html import escape
from pathlib import Path, PurePosixPath

from sitegen.config import ClipConfig, Config
from sitegen.errors import Diagnostics
from sitegen.i18n import strings as interface_strings
from sitegen.integrations import Integration
from sitegen.links import url_quote
from sitegen.nav import Node, PageInput
from sitegen.output import OutFile, file_digest
from sitegen.pages import root_prefix

OUT_NAMES = {
    "video": "clip.webm",
    "poster": "poster.png",
    "csv": "data.csv",
    "json": "data.json",
    "plot": "path.svg",
}


def _sims_code_digest() -> str:
    import sims

    h = hashlib.sha256()
    root = Path(sims.__file__).resolve().parent
    for f in sorted([*root.rglob("*.py"), *root.rglob("*.json")]):  # code, bundled scenes
        h.update(f.relative_to(root).as_posix().encode())
        h.update(f.read_bytes())
    return h.hexdigest()


class SimsIntegration(Integration):
    def __init__(self, config: Config, cache_dir: Path, opts):
        assert config.sims is not None
        self.config, self.sims, self.opts = config, config.sims, opts
        self.cache_dir = cache_dir / "clips"
        self.results: dict[str, object] = {}
        self.failed: dict[str, str] = {}
        self.pending: set[str] = set()  # not rendered yet (a build that renders no clips)
        self._files: dict[str, OutFile] = {}
        self.strings = interface_strings(config.language)
        self._clips = {clip.name: clip for clip in self.sims.clips}

    def clip_title(self, name: str) -> str:
        """The clip's ``title:`` (gallery heading, caption link), else its name."""
        clip = self._clips.get(name)
        return (clip.title if clip is not None else None) or name

    def fingerprint(self) -> str:
        h = hashlib.sha256(repr(self.sims).replace(str(self.config.root), ".").encode())
        h.update(_sims_code_digest().encode())
        for clip in self.sims.clips:
            for path in (clip.script, self.config.root / (clip.scene or "")):
                if path is not None and path.is_file():  # a script, a scene file
                    h.update(path.read_bytes())
        if getattr(self.opts, "retry_failed", False):
            h.update(b"retry-failed")  # a retry is never "up to date"
        if not self._renders():
            h.update(b"no-render")  # so the next full build renders what this one left out
        return "sims:" + h.hexdigest()

    def _renders(self) -> bool:
        """False for a quick build (``BuildOptions.render_clips``): cached clips only."""
        return bool(getattr(self.opts, "render_clips", True))

    def _relative(self, path: Path) -> str:
        """A path as the project names it (relative to sitegen.yml): portable, for keys."""
        try:
            return path.resolve().relative_to(self.config.root.resolve()).as_posix()
        except ValueError:
            return path.name

    def _spec(self, clip: ClipConfig):
        from sims.clips import ClipSpec

        common = {
            "width": self.sims.width,
            "height": self.sims.height,
            "fps": self.sims.fps,
            "seconds": clip.seconds,
            "seed": clip.seed,
            "speed": clip.speed,
            "timeout": clip.timeout,
            "camera": clip.camera,
            "trail": clip.trail,
        }
        if clip.script is not None:
            scene = clip.scene
            if scene and (self.config.root / scene).is_file():  # a scene file of the project
                scene = str((self.config.root / scene).resolve())
            params = {"scene": scene}
            if clip.after is not None:
                params["after"] = clip.after
            return ClipSpec(
                name=clip.name,
                scenario=str(clip.script),
                kind="script",
                params=params,
                label=self._relative(clip.script),
                **common,
            )
        return ClipSpec(name=clip.name, scenario=clip.scenario, **common)

    def prepare(self, diags: Diagnostics, state) -> None:
        from sims.clips import render_clips

        config_file = str(
            self.config.source_file.name if self.config.source_file else "sitegen.yml"
        )
        from sitegen.progress import ClipProgress

        specs = [self._spec(clip) for clip in self.sims.clips]

        shown = ClipProgress(live=self.opts.is_tty, log=self.opts.log)
        try:
            results = (
                render_clips(
                    specs,
                    self.cache_dir,
                    jobs=self.sims.jobs,
                    progress=shown,
                    timeout=self.sims.timeout,
                    retry_failed=getattr(self.opts, "retry_failed", False),
                    render=self._renders(),
                )
                if specs
                else []
            )
        finally:
            shown.close()
        for r in results:
            if r.pending:  # a quick build (sitegen serve's first): no warning, shown later
                self.pending.add(r.name)
            elif not r.ok:
                shown_instead = (
                    " (showing the previous render, marked stale)"
                    if r.stale and r.files
                    else " (a placeholder is shown)"
                )
                diags.warning(
                    config_file, None, f"sims.clips[{r.name}]", f"{r.error}{shown_instead}"
                )
                self.failed[r.name] = r.error or "failed"
            if r.files:
                self.results[r.name] = r
                for key, path in sorted(r.files.items()):
                    if key in OUT_NAMES and Path(path).is_file():
                        self._files[f"clips/{r.name}/{OUT_NAMES[key]}"] = OutFile(
                            file_digest(Path(path)), source=Path(path)
                        )

    def files(self) -> dict[str, OutFile]:
        return dict(self._files)

    def _has(self, name: str, key: str) -> bool:
        return f"clips/{name}/{OUT_NAMES[key]}" in self._files

    def video_html(self, name: str, root: str, caption: bool = True) -> str:
        r = self.results[name]
        meta = r.meta
        base = root + url_quote(f"clips/{name}/")
        w, h = meta.get("width", self.sims.width), meta.get("height", self.sims.height)
        poster = f' poster="{base}poster.png"' if self._has(name, "poster") else ""
        out = [
            f'<figure class="clip" id="clip-{escape(name, quote=True)}">',
            f'<video controls muted playsinline preload="metadata" '
            f'width="{int(w)}" height="{int(h)}"{poster}>',
            f'<source src="{base}clip.webm" type="video/webm"></video>',
        ]
        if caption:
            gallery = (
                root
                + url_quote(f"{self._section()}/index.html")
                + f"#clip-{escape(name, quote=True)}"
            )
            t = self.strings
            stale = f' <span class="stale">({escape(t["stale"])})</span>' if r.stale else ""
            length = f"{float(meta.get('duration', 0)):.1f} {t['seconds_unit']}"
            out.append(
                f"<figcaption>{escape(str(meta.get('description', name)))} · {escape(length)} · "
                f'<a href="{gallery}">{escape(self.clip_title(name))}</a>{stale}</figcaption>'
            )
        out.append("</figure>")
        return "\n".join(out)

    def placeholder_html(self, name: str, root: str, caption: bool = True) -> str:
        """The poster area of a clip with no render: the clip's size, the error inside."""
        t = self.strings
        waiting = name in self.pending and name not in self.failed
        error = t["rendering"] if waiting else self.failed.get(name, t["not_rendered"])
        status = t["rendering"] if waiting else t["not_rendered"]
        w, h = int(self.sims.width), int(self.sims.height)
        anchor = escape(f"clip-{name}", quote=True)
        box = (
            f"aspect-ratio:{w}/{h};width:100%;max-width:{w}px;display:flex;flex-direction:column;"
            "justify-content:center;gap:6px;padding:12px;box-sizing:border-box;background:#222;"
            "color:#eee;border-radius:6px;overflow:auto;font-size:.9rem"
        )
        out = [
            f'<figure class="clip {"clip-pending" if waiting else "clip-failed"}" id="{anchor}">',
            f'<div class="clip-placeholder" role="img" '
            f'aria-label="{escape(self.clip_title(name), quote=True)}: '
            f'{escape(status, quote=True)}" style="{box}">',
            f"<strong>{escape(self.clip_title(name))}: {escape(status)}</strong>",
            f"<code>{escape(error)}</code></div>",
        ]
        if caption:
            gallery = root + url_quote(f"{self._section()}/index.html") + f"#{anchor}"
            note = "" if waiting else f' <span class="stale">({escape(t["render_failed"])})</span>'
            link = f'<a href="{gallery}">{escape(self.clip_title(name))}</a>'
            out.append(f"<figcaption>{link}{note}</figcaption>")
        out.append("</figure>")
        return "\n".join(out)

    def _section(self) -> str:
        return self.sims.section.strip("/") or "gallery"

    def directives(self) -> dict:
        def clip(arg: str, node: Node) -> str:
            name = arg.strip()
            if name in self.results:
                return self.video_html(name, root_prefix(node.url))
            if name in self.failed or name in self.pending:
                return self.placeholder_html(name, root_prefix(node.url))
            known = ", ".join(c.name for c in self.sims.clips) or "none configured"
            raise LookupError(f"no clip named '{name}' in sitegen.yml (known: {known})")

        return {"clip": clip}

    def pages(self, strings: dict[str, str]) -> list[PageInput]:
        """The gallery: every clip with poster, length, parameters, data, plot and source."""
        rel = PurePosixPath(self._section(), "index.md")
        root = "../" * (len(rel.parts) - 1)
        parts, toc = [], []
        for clip in self.sims.clips:
            anchor = f"clip-{clip.name}"
            if clip.name not in self.results:
                toc.append(
                    {"id": f"{anchor}-h", "title": self.clip_title(clip.name), "children": []}
                )
                heading = f'<h2 id="{escape(anchor)}-h">{escape(self.clip_title(clip.name))}</h2>'
                parts.append(
                    f'<section class="gallery-item">{heading}\n'
                    f"{self.placeholder_html(clip.name, root, caption=False)}\n"
                    f"{self._source_html(self._source_meta(clip), strings)}</section>"
                )
                continue
            r = self.results[clip.name]
            meta = r.meta
            toc.append({"id": f"{anchor}-h", "title": self.clip_title(clip.name), "children": []})
            base = root + url_quote(f"clips/{clip.name}/")
            params = json.dumps(meta.get("params", {}), ensure_ascii=False, sort_keys=True)
            rows = [
                (
                    strings["duration"],
                    f"{float(meta.get('duration', 0)):.1f} {strings['seconds_unit']} · "
                    f"{meta.get('frames', '?')} {strings['frames']} · "
                    f"{meta.get('width')}×{meta.get('height')} @ {meta.get('fps')} fps",
                ),
                (strings["parameters"], f"{strings['seed']} {meta.get('seed')} · {params}"),
                (strings["renderer"], str(meta.get("renderer", ""))),
            ]
            dl = "".join(f"<dt>{escape(k)}</dt><dd>{escape(v)}</dd>" for k, v in rows)
            downloads = " · ".join(
                f'<a href="{base}{OUT_NAMES[k]}" download>{label}</a>'
                for k, label in (("csv", "CSV"), ("json", "JSON"))
                if self._has(clip.name, k)
            )
            dl += f"<dt>{escape(strings['downloads'])}</dt><dd>{downloads}</dd>"
            plot = (
                f'<img class="plot" src="{base}path.svg" '
                f'alt="{escape(strings["trajectory"])}: {escape(clip.name)}" loading="lazy">'
                if self._has(clip.name, "plot")
                else ""
            )
            heading = f'<h2 id="{escape(anchor)}-h">{escape(self.clip_title(clip.name))}</h2>'
            description = escape(str(meta.get("description", "")))
            source = self._source_html(self._source_meta(clip, meta), strings)
            parts.append(
                f'<section class="gallery-item">{heading}\n'
                f"{self.video_html(clip.name, root, caption=False)}\n<p>{description}</p>\n"
                f"<dl>{dl}</dl>\n{plot}\n{source}</section>"
            )
            # the figure carries id clip-NAME, so directive captions link straight to it
        body = "\n".join(parts)
        return [
            PageInput(
                rel,
                {"title": self.sims.title, "weight": 90},
                "",
                True,
                None,
                "index",
                body_html=body,
                toc=toc,
                digest=hashlib.sha256(body.encode()).hexdigest(),
            )
        ]

    def _source_meta(self, clip: ClipConfig, meta: dict | None = None) -> dict:
        """Where the clip's source is: a script named in sitegen.yml, else the render's meta."""
        if clip.script is not None:
            return {"source": self._relative(clip.script)}
        if meta is None and clip.scenario:
            try:
                from sims.cache import display_path
                from sims.scenarios import get_scenario

                return {"source": display_path(get_scenario(clip.scenario).source_path)}
            except (KeyError, ImportError):
                return {}
        return meta or {}

    def _source_html(self, meta: dict, strings: dict[str, str]) -> str:
        from pygments import highlight
        from pygments.formatters import HtmlFormatter
        from pygments.lexers import PythonLexer

        path = meta.get("source") or meta.get("source_path")
        candidates = [Path(path)] if path else []
        if path and not Path(path).is_absolute():
            from sims.cache import ROOT_DIR  # sims records package-relative paths

            candidates = [ROOT_DIR / path, self.config.root / path]
        source = next((p for p in candidates if p.is_file()), None)
        if source is None:
            return ""
        code = highlight(
            source.read_text(encoding="utf-8", errors="replace"),
            PythonLexer(),
            HtmlFormatter(cssclass="highlight", wrapcode=True),
        )
        return (
            f"<details><summary>{escape(strings['source'])}: "
            f"<code>{escape(str(path))}</code></summary>\n"
            f"{code}</details>"
        )
