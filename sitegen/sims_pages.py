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
from pathlib import Path, PurePosixPath

from located.paths import public_paths
from sitegen import clip_view as words
from sitegen.config import ClipConfig, Config
from sitegen.errors import Diagnostics
from sitegen.i18n import strings as interface_strings
from sitegen.integrations import Integration
from sitegen.links import url_quote
from sitegen.nav import Node, PageInput
from sitegen.output import OutFile, file_digest
from sitegen.pages import root_prefix
from sitegen.partials import Partials, trusted

OUT_NAMES = {  # as sims.clip_cache.FILES (kept here: importing sims costs a quick build time)
    "video": "clip.webm",
    "mp4": "clip.mp4",
    "poster": "poster.png",
    "csv": "data.csv",
    "json": "data.json",
    "plot": "path.svg",
    "series": "series.svg",
    "replay": "replay.glb",
    "replay_js": "replay.js",
}
VIEWER = "assets/replay/replay.js"  # the replay viewer (templates/assets/replay/)
THREE = "assets/replay/three.min.js"


def sims_code_key() -> str:
    """The code that renders clips (:func:`located.code_keys.code_key`): part of the gallery's
    fingerprint."""
    from located.code_keys import code_key

    return code_key("sims.clips", "sims.clip_worker")


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
        self.partials = Partials(config)
        self._viewer_pages: set[str] = set()  # pages that already load the replay viewer
        self._page = ""  # the page whose clips are being rendered

    def clip_title(self, name: str) -> str:
        """The clip's ``title:`` (gallery heading, caption link), else its name."""
        clip = self._clips.get(name)
        return (clip.title if clip is not None else None) or name

    def fingerprint(self) -> str:
        h = hashlib.sha256(repr(self.sims).replace(str(self.config.root), ".").encode())
        h.update(sims_code_key().encode())
        for clip in self.sims.clips:
            for path in (clip.script, self.config.root / (clip.scene or ""), clip.keys):
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
            "formats": tuple(clip.formats or self.sims.formats),
        }
        if clip.script is not None:
            scene = clip.scene
            if scene and (self.config.root / scene).is_file():  # a scene file of the project
                scene = str((self.config.root / scene).resolve())
            params = {"scene": scene}
            if clip.after is not None:
                params["after"] = clip.after
            if clip.keys is not None:
                params["keys"] = str(clip.keys.resolve())
            if clip.args:
                params["args"] = list(clip.args)
            if clip.python:
                params["python"] = clip.python
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
        from sims.render import fallback_note

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
        note = fallback_note(r.fallback for r in results)  # why EGL fell back, once a build
        if note:
            self.opts.log(note)
        for r in results:
            if r.pending:  # a quick build (sitegen serve's first): no warning, shown later
                self.pending.add(r.name)
            elif not r.ok:
                shown_instead = (
                    " (showing the previous render, marked stale)"
                    if r.stale and r.files
                    else " (a placeholder is shown)"
                )
                error = public_paths(r.error or "failed", self.config.root)  # published
                diags.warning(config_file, None, f"sims.clips[{r.name}]", f"{error}{shown_instead}")
                self.failed[r.name] = error
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

    def _inline_svg(self, name: str, key: str):
        """A plot of the clip as inline markup (so the theme's colours apply), or None."""
        r = self.results.get(name)
        path = getattr(r, "files", {}).get(key) if r is not None else None
        if path is None or not Path(path).is_file():
            return None
        text = Path(path).read_text(encoding="utf-8")
        return trusted(text) if text.startswith("<svg ") else None  # written by sims/plot.py

    def clip_view(self, name: str, root: str, caption: bool = True, in_page: bool = False) -> dict:
        """What ``partials/clip.html`` shows of a clip: its replay (3D viewer over the poster) or
        its video, or a placeholder of its size with the reason it has none; a caption
        linking to the gallery unless ``caption`` is False (the gallery itself)."""
        t = self.strings
        anchor = f"clip-{name}"
        title = self.clip_title(name)
        view: dict = {"name": name, "anchor": anchor, "title": title, "kind": "placeholder"}
        gallery = root + url_quote(f"{self._section()}/index.html") + "#" + url_quote(anchor)
        view["video"] = None
        if name in self.results:
            r = self.results[name]
            meta = r.meta
            formats = list(meta.get("formats") or ["video"])
            w, h = meta.get("width", self.sims.width), meta.get("height", self.sims.height)
            base = root + url_quote(f"clips/{name}/")
            poster = base + "poster.png" if self._has(name, "poster") else None
            videos = [
                {"src": base + OUT_NAMES[k], "type": kind}
                for k, kind in (("video", "video/webm; codecs=vp8"), ("mp4", "video/mp4"))
                if self._has(name, k)
            ]
            replay = "replay" in formats and self._has(name, "replay_js")
            view["kind"] = "replay" if replay else "video"
            if replay:
                speed = float(meta.get("speed") or 1)
                view["replay"] = {
                    "data": base + OUT_NAMES["replay_js"],
                    "glb": base + OUT_NAMES["replay"],
                    "three": root + THREE,
                    "viewer": root + VIEWER,
                    # a page's figures each carry the viewer (expand_directives keeps the
                    # first, by its data-once: a page and its slide deck alike, in any order)
                    "load_viewer": in_page or self._first_replay_on(),
                    "width": int(w),
                    "height": int(h),
                    "duration": f"{float(meta.get('duration', 0)):g}",
                    "speeds": words.speed_choices(speed),
                    "poster": poster,
                    "series": self._inline_svg(name, "series"),
                    "t": {k: t[k] for k in words.VIEWER_WORDS},
                    "label": t["replay_label"].format(title=title),
                    "alt": t["first_frame"].format(title=title),
                    "unit": t["seconds_unit"],
                    "videos": videos,
                }
            else:
                view["video"] = {
                    "base": base,  # project templates older than MP4 name clip.webm from here
                    "sources": videos,
                    "width": int(w),
                    "height": int(h),
                    "poster": poster,
                }
            view["caption"] = caption and {
                "href": gallery,
                "facts": words.facts(meta, t, replay=replay),
                "note": t["stale"] if r.stale else "",
            }
            return view
        waiting = name in self.pending and name not in self.failed
        view["placeholder"] = {
            "waiting": waiting,
            "status": t["rendering"] if waiting else t["not_rendered"],
            "error": t["rendering"] if waiting else self.failed.get(name, t["not_rendered"]),
            "width": int(self.sims.width),
            "height": int(self.sims.height),
        }
        view["caption"] = caption and {
            "href": gallery,
            "note": "" if waiting else t["render_failed"],
        }
        return view

    def _first_replay_on(self) -> bool:
        """Whether this replay's figure in the gallery loads the viewer script: the first."""
        if self._page in self._viewer_pages:
            return False
        self._viewer_pages.add(self._page)
        return True

    def clip_html(self, name: str, root: str) -> str:
        """A clip's figure in a page, with its caption, from the theme's ``partials/clip.html``."""
        return self.partials.render("clip", clip=self.clip_view(name, root, in_page=True))

    def _section(self) -> str:
        return self.sims.section.strip("/") or "gallery"

    def directives(self) -> dict:
        def clip(arg: str, node: Node) -> str:
            name = arg.strip()
            if name in self.results or name in self.failed or name in self.pending:
                return self.clip_html(name, root_prefix(node.url))
            known = ", ".join(c.name for c in self.sims.clips) or "none configured"
            raise LookupError(f"no clip named '{name}' in sitegen.yml (known: {known})")

        return {"clip": clip}

    def pages(self, strings: dict[str, str]) -> list[PageInput]:
        """The gallery: every clip with poster, length, parameters, data, plot and source."""
        rel = PurePosixPath(self._section(), "index.md")
        root = "../" * (len(rel.parts) - 1)
        self._page = rel.as_posix()
        items, toc = [], []
        for clip in self.sims.clips:
            view = self.clip_view(clip.name, root, caption=False)
            toc.append({"id": f"{view['anchor']}-h", "title": view["title"], "children": []})
            item: dict = {"clip": view, "source": None}
            if clip.name not in self.results:
                item["source"] = self._source_view(self._source_meta(clip), strings)
                items.append(item)
                continue
            meta = self.results[clip.name].meta
            formats = list(meta.get("formats") or ["video"])
            base = root + url_quote(f"clips/{clip.name}/")
            item["rows"] = [
                (strings["duration"], words.length_text(meta, strings, formats)),
                (strings["parameters"], words.parameter_text(meta, strings)),
            ]
            item["downloads_label"] = strings["downloads"]
            item["downloads"] = [
                {"href": base + OUT_NAMES[k], "label": label}
                for k, label in (
                    ("csv", "CSV"),
                    ("json", "JSON"),
                    ("replay", strings["replay_file"]),
                    ("video", f"{strings['video']} (WebM)"),
                    ("mp4", f"{strings['video']} (MP4)"),
                )
                if self._has(clip.name, k)
            ]
            path_plot = self._inline_svg(clip.name, "plot")
            item["plot"] = path_plot is not None and {
                "svg": path_plot,
                "label": f"{strings['trajectory']}: {view['title']}",
            }
            series = view["kind"] != "replay" and self._inline_svg(clip.name, "series")
            item["series"] = series and {"svg": series, "label": strings["series"]}
            item["description"] = clip.description or str(meta.get("description", ""))
            item["description_lang"] = (
                "en"
                if clip.description is None and not self.config.language.startswith("en")
                else ""
            )
            item["source"] = self._source_view(self._source_meta(clip, meta), strings)
            items.append(item)
        body = self.partials.render("gallery", items=items)
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
                from sims.clip_cache import display_path
                from sims.scenarios import get_scenario

                return {"source": display_path(get_scenario(clip.scenario).source_path)}
            except (KeyError, ImportError):
                return {}
        return meta or {}

    def _source_view(self, meta: dict, strings: dict[str, str]) -> dict | None:
        """The clip's source listing for the gallery, highlighted; None when it is not found."""
        from pygments import highlight
        from pygments.formatters import HtmlFormatter
        from pygments.lexers import PythonLexer

        path = meta.get("source") or meta.get("source_path")
        candidates = [Path(path)] if path else []
        if path and not Path(path).is_absolute():
            from sims.clip_cache import ROOT_DIR  # sims records package-relative paths

            candidates = [ROOT_DIR / path, self.config.root / path]
        source = next((p for p in candidates if p.is_file()), None)
        if source is None:
            return None
        code = highlight(
            source.read_text(encoding="utf-8", errors="replace"),
            PythonLexer(),
            HtmlFormatter(cssclass="highlight", wrapcode=True),
        )
        return {"label": strings["source"], "path": str(path), "html": trusted(code)}
