"""Simulation clips in the site: render (or reuse) the configured clips, publish their files,
add the gallery page and the ``::: clip NAME`` directive.

Rendering is delegated to :func:`sims.clips.render_clips`, which caches by content hash and
renders independent clips in parallel; a clip that fails keeps its previous good render
(marked stale) and is reported by name, the rest of the site still builds.
"""

from __future__ import annotations

import hashlib
import json
import sys
from html import escape
from pathlib import Path, PurePosixPath

from sitegen.config import ClipConfig, Config
from sitegen.errors import Diagnostics
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
    for f in sorted(root.rglob("*.py")):
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
        self._files: dict[str, OutFile] = {}

    def fingerprint(self) -> str:
        h = hashlib.sha256(repr(self.sims).encode())
        h.update(_sims_code_digest().encode())
        for clip in self.sims.clips:
            if clip.script is not None and clip.script.is_file():
                h.update(clip.script.read_bytes())
        return "sims:" + h.hexdigest()

    def _spec(self, clip: ClipConfig):
        from sims.clips import ClipSpec

        common = {
            "width": self.sims.width,
            "height": self.sims.height,
            "fps": self.sims.fps,
            "seconds": clip.seconds,
            "seed": clip.seed,
        }
        if clip.script is not None:
            import sims.remote_api  # noqa: F401  (registers the "script" clip kind)

            params = {"scene": clip.scene}
            if clip.after is not None:
                params["after"] = clip.after
            return ClipSpec(
                name=clip.name, scenario=str(clip.script), kind="script", params=params, **common
            )
        return ClipSpec(name=clip.name, scenario=clip.scenario, **common)

    def prepare(self, diags: Diagnostics, state) -> None:
        from sims.clips import render_clips

        config_file = str(
            self.config.source_file.name if self.config.source_file else "sitegen.yml"
        )
        specs = []
        for clip in self.sims.clips:
            if clip.script is not None and not clip.script.is_file():
                diags.warning(
                    config_file,
                    None,
                    f"sims.clips[{clip.name}].script",
                    f"script not found: {clip.script}",
                )
                self.failed[clip.name] = "script not found"
                continue
            specs.append(self._spec(clip))
        total, done = len(specs), [0]
        tty = self.opts.is_tty

        def progress(event) -> None:
            if event.status == "started":
                if not tty:
                    self.opts.log(f"clip {event.name}: rendering")
                return
            done[0] += 1
            text = {
                "cached": "cached",
                "done": f"rendered in {event.seconds:.1f}s",
                "failed": f"FAILED: {event.error}",
            }.get(event.status, event.status)
            if tty:
                bar = "#" * int(20 * done[0] / max(total, 1))
                sys.stderr.write(
                    f"\rclips [{bar:<20}] {done[0]}/{total} {event.name}: {text}\033[K"
                )
                if done[0] == total:
                    sys.stderr.write("\n")
                sys.stderr.flush()
            else:
                self.opts.log(f"clip {event.name}: {text}")

        results = (
            render_clips(
                specs,
                self.cache_dir,
                jobs=self.sims.jobs,
                progress=progress,
                timeout=self.sims.timeout,
            )
            if specs
            else []
        )
        for r in results:
            if not r.ok:
                stale = " (showing the previous render)" if r.stale and r.files else ""
                diags.warning(config_file, None, f"sims.clips[{r.name}]", f"{r.error}{stale}")
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
            f'<video controls muted playsinline preload="metadata" width="{int(w)}" height="{int(h)}"{poster}>',
            f'<source src="{base}clip.webm" type="video/webm"></video>',
        ]
        if caption:
            gallery = (
                root
                + url_quote(f"{self._section()}/index.html")
                + f"#clip-{escape(name, quote=True)}"
            )
            stale = ' <span class="stale">(stale: last render failed)</span>' if r.stale else ""
            out.append(
                f"<figcaption>{escape(str(meta.get('description', name)))} · "
                f'{float(meta.get("duration", 0)):.1f} s · <a href="{gallery}">{escape(name)}</a>{stale}</figcaption>'
            )
        out.append("</figure>")
        return "\n".join(out)

    def _section(self) -> str:
        return self.sims.section.strip("/") or "gallery"

    def directives(self) -> dict:
        def clip(arg: str, node: Node) -> str:
            name = arg.strip()
            if name in self.results:
                return self.video_html(name, root_prefix(node.url))
            if name in self.failed:
                raise LookupError(f"clip '{name}' has no render: {self.failed[name]}")
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
                parts.append(
                    f'<section class="gallery-item"><h2 id="{escape(anchor)}-missing">{escape(clip.name)}</h2>'
                    f'<p class="stale">{escape(self.failed.get(clip.name, "not rendered"))}</p></section>'
                )
                continue
            r = self.results[clip.name]
            meta = r.meta
            toc.append({"id": f"{anchor}-h", "title": clip.name, "children": []})
            base = root + url_quote(f"clips/{clip.name}/")
            params = json.dumps(meta.get("params", {}), ensure_ascii=False, sort_keys=True)
            rows = [
                (
                    strings["duration"],
                    f"{float(meta.get('duration', 0)):.1f} s · {meta.get('frames', '?')} frames · "
                    f"{meta.get('width')}×{meta.get('height')} @ {meta.get('fps')} fps",
                ),
                (strings["parameters"], f"seed {meta.get('seed')} · {params}"),
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
                f'<img class="plot" src="{base}path.svg" alt="{escape(strings["trajectory"])}: {escape(clip.name)}" loading="lazy">'
                if self._has(clip.name, "plot")
                else ""
            )
            parts.append(
                f'<section class="gallery-item"><h2 id="{escape(anchor)}-h">{escape(clip.name)}</h2>\n'
                f"{self.video_html(clip.name, root, caption=False)}\n<p>{escape(str(meta.get('description', '')))}</p>\n"
                f"<dl>{dl}</dl>\n{plot}\n{self._source_html(meta, strings)}</section>"
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
            f"<details><summary>{escape(strings['source'])}: <code>{escape(str(path))}</code></summary>\n"
            f"{code}</details>"
        )
