"""Sweeps in the site (``sims: sweeps:`` in sitegen.yml): run them (or reuse them), publish
results.csv and results.jsonl, and add a page per sweep with a sortable table, a scatter plot
and a histogram (inline SVG in the theme's colours, sitegen/sweep_plots.py) and the best runs
as clips.

The site's results.jsonl leaves out wall seconds and hosts, so a rebuilt site has the same bytes.
A sweep builds like a clip: cached by the content of its inputs (the script's bytes, the scene,
the argument file, the planned runs and seeds, the limits, and the sims package's code), so a
build that changed none of them runs nothing. Its runs go to ``sims.executor`` (local worker
processes, or Ray: the running cluster). A sweep never takes the site down: one that cannot
run is a warning (an error under ``--strict``) and its page says why; failed runs are rows.
The best runs (by ``key``, ``order``) are rendered as clips through :func:`sims.clips.render_clips`
with the run's seed, into the same clip cache as the gallery's. With ``sims.executor: ray`` the
build's clips (the gallery's too) are rendered on Ray as well (``sims.clip_pool.EXECUTOR``).
"""

from __future__ import annotations

import hashlib
import json
import shutil
import sys
import tempfile
from pathlib import Path, PurePosixPath
from typing import Any

from sitegen.config import Config
from sitegen.errors import Diagnostics
from sitegen.integrations import Integration
from sitegen.links import url_quote
from sitegen.nav import PageInput
from sitegen.output import OutFile, file_digest
from sitegen.partials import Partials, trusted
from sitegen.sweep_config import SweepConfig
from sitegen.sweep_plots import histogram, scatter

TABLE_ROWS = 200  # rows shown on the page; results.csv has every run
WORDS = {
    "en": {
        "runs": "runs",
        "run": "run",
        "failed": "failed",
        "best": "Best runs by",
        "table": "Runs",
        "download": "All runs",
        "shown": "the first {n} by {key} shown; every run is in results.csv",
        "seed": "seed",
        "none": "No run reported",
        "not_run": "This sweep has not run",
        "clip_failed": "no clip",
        "where": "Final position of every run",
        "spread": "Distribution of",
        "sort": "Click a column heading to sort by it.",
    },
    "zh-TW": {
        "runs": "次執行",
        "run": "執行",
        "failed": "失敗",
        "best": "最佳執行, 依",
        "table": "所有執行",
        "download": "全部結果",
        "shown": "依 {key} 顯示前 {n} 筆; 所有執行都在 results.csv",
        "seed": "種子",
        "none": "沒有執行回報",
        "not_run": "這個掃描尚未執行",
        "clip_failed": "沒有影片",
        "where": "每次執行的最終位置",
        "spread": "分布:",
        "sort": "點選欄位標題即可排序。",
    },
}


def _digest(*parts: bytes) -> str:
    h = hashlib.sha256()
    for part in parts:
        h.update(hashlib.sha256(part).digest())
    return h.hexdigest()


def key_value(record: Any, key: str | None) -> float | None:
    """A run's value of ``key``: a reported result, else ``final_x``/``final_<joint>``."""
    if not key:
        return None
    value = record.results.get(key)
    if value is None and key.startswith("final_"):
        name = key[len("final_") :]
        value = record.final.get(name, record.final.get("joints", {}).get(name))
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def best_runs(records: list[Any], sweep: SweepConfig) -> list[Any]:
    """The ``best`` runs that ended well, by ``key`` (``order``), ties by index."""
    scored = [(key_value(r, sweep.key), r) for r in records if r.ok]
    scored = [(v, r) for v, r in scored if v is not None]
    sign = -1.0 if sweep.order == "max" else 1.0
    scored.sort(key=lambda t: (sign * t[0], t[1].index))
    return [r for _, r in scored[: sweep.best]]


class SweepsIntegration(Integration):
    def __init__(self, config: Config, cache_dir: Path, opts: Any):
        assert config.sims is not None
        self.config, self.sims, self.opts = config, config.sims, opts
        self.cache_dir = cache_dir / "sweeps"
        self.clip_dir = cache_dir / "clips"
        self.records: dict[str, list[Any]] = {}
        self.failed: dict[str, str] = {}
        self.clips: dict[str, dict[int, dict[str, str]]] = {}  # sweep -> run -> kind -> file
        self._files: dict[str, OutFile] = {}
        self.partials = Partials(config)
        lang = config.language if config.language in WORDS else "en"
        self.words = WORDS[lang]
        from sims import clip_pool

        # the build's clips go to the same executor as its sweeps (made before any prepare)
        clip_pool.EXECUTOR = self.sims.executor

    # -- inputs ------------------------------------------------------------------------------
    def _relative(self, path: Path) -> str:
        try:
            return path.resolve().relative_to(self.config.root.resolve()).as_posix()
        except ValueError:
            return path.name

    def _scene(self, sweep: SweepConfig) -> str:
        path = self.config.root / sweep.scene
        return str(path.resolve()) if path.is_file() else sweep.scene

    def _plan(self, sweep: SweepConfig):
        from sims.sweeps.plan import parse_seeds, plan_runs

        seeds = parse_seeds(sweep.seeds, "seeds") if sweep.seeds else None
        return plan_runs(seeds, sweep.grid, sweep.args, sweep.seed)

    def _key(self, sweep: SweepConfig, planned: list[Any]) -> str:
        from located.code_keys import code_key

        scene = self._scene(sweep)
        inputs = {
            "runs": [[r.index, r.seed, list(r.args)] for r in planned],
            "scene": scene if not Path(scene).is_file() else "file",
            "seconds": sweep.seconds,
            "timeout": sweep.timeout,
        }
        files = [sweep.script.read_bytes()]
        if Path(scene).is_file():
            files.append(Path(scene).read_bytes())
        code = code_key("sims.runs", "sims.sweeps.worker")  # the code a sweep's runs run
        return _digest(json.dumps(inputs, sort_keys=True).encode(), *files, code.encode())

    def fingerprint(self) -> str:
        h = hashlib.sha256(repr(self.sims.sweeps).replace(str(self.config.root), ".").encode())
        h.update(self.sims.executor.encode())
        for sweep in self.sims.sweeps:
            for path in (sweep.script, sweep.args, self.config.root / sweep.scene):
                if path is not None and path.is_file():
                    h.update(path.read_bytes())
        if not getattr(self.opts, "render_clips", True):
            h.update(b"no-render")
        return "sweeps:" + h.hexdigest()

    # -- running -----------------------------------------------------------------------------
    def prepare(self, diags: Diagnostics, state: Any) -> None:
        where = self.config.source_file.name if self.config.source_file else "sitegen.yml"
        for i, sweep in enumerate(self.sims.sweeps):
            try:
                self.records[sweep.name] = self._run(sweep)
            except _NotYet:  # a quick build (sitegen serve's first): no warning, run later
                self.failed[sweep.name] = self.words["not_run"]
                continue
            except Exception as exc:  # never the whole site: this sweep's page says why
                text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                self.failed[sweep.name] = text
                diags.warning(where, None, f"sims.sweeps[{i}]", f"{sweep.name}: {text}")
                continue
            self._publish(sweep)
            self._best_clips(sweep, diags, where, i)

    def _run(self, sweep: SweepConfig) -> list[Any]:
        from sims import runs
        from sims.sweeps import results
        from sims.sweeps.progress import SweepProgress

        if not sweep.script.is_file():
            raise FileNotFoundError(f"{self._relative(sweep.script)}: no such script file")
        planned = self._plan(sweep)
        entry = self.cache_dir / self._key(sweep, planned)
        if (entry / results.JSONL_NAME).is_file():
            return results.read_jsonl(entry / results.JSONL_NAME)
        if not getattr(self.opts, "render_clips", True):
            raise _NotYet
        settings = runs.settings_for(
            sweep.script,
            self._scene(sweep),
            seconds=sweep.seconds,
            timeout=sweep.timeout or runs.DEFAULT_TIMEOUT,
            cwd=self.config.root,
            label=self._relative(sweep.script),
        )
        self.opts.log(f"sweep {sweep.name}: {len(planned)} runs")
        self.cache_dir.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".tmp-", dir=self.cache_dir))
        shown = SweepProgress(len(planned), stream=sys.stderr, live=self.opts.is_tty)
        try:
            executor = self.sims.executor
            address = "auto" if executor == "ray" else None
            outcome = runs.sweep(settings, planned, tmp, executor, address=address, progress=shown)
            shown.close()
            if entry.exists():
                shutil.rmtree(tmp, ignore_errors=True)
            else:
                tmp.replace(entry)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        return outcome.records

    def _publish(self, sweep: SweepConfig) -> None:
        from sims.sweeps import results

        records = self.records[sweep.name]
        folder = self.cache_dir / "published" / sweep.name
        folder.mkdir(parents=True, exist_ok=True)
        for name, text in (
            (results.CSV_NAME, results.csv_text(records)),
            (results.JSONL_NAME, results.jsonl_text(records, varying=False)),
        ):
            path = folder / name
            if not path.is_file() or path.read_text(encoding="utf-8") != text:
                path.write_text(text, encoding="utf-8")
            self._files[f"sweeps/{sweep.name}/{name}"] = OutFile(file_digest(path), source=path)

    def _best_clips(self, sweep: SweepConfig, diags: Diagnostics, where: str, i: int) -> None:
        from sims.clips import ClipSpec, render_clips

        best = best_runs(self.records[sweep.name], sweep)
        specs = []
        for r in best:
            seconds = sweep.seconds if r.status == "cut" else round(r.sim_seconds + 0.1, 3)
            specs.append(
                ClipSpec(
                    name=f"sweep-{sweep.name}-run-{r.index}",
                    scenario=str(sweep.script),
                    kind="script",
                    width=self.sims.width,
                    height=self.sims.height,
                    fps=self.sims.fps,
                    seconds=seconds,
                    seed=r.seed,
                    params={"scene": self._scene(sweep), **_clip_args(r)},
                    speed=2.0,
                    label=self._relative(sweep.script),
                )
            )
        if not specs:
            return
        render = bool(getattr(self.opts, "render_clips", True))
        got = render_clips(specs, self.clip_dir, jobs=self.sims.jobs, timeout=self.sims.timeout,
                           render=render)  # fmt: skip
        self.clips[sweep.name] = {}
        for r, result in zip(best, got, strict=True):
            if not result.files:
                if not result.pending:
                    diags.warning(
                        where, None, f"sims.sweeps[{i}]", f"run {r.index}: {result.error}"
                    )
                continue
            files = {}
            for kind, path in sorted(result.files.items()):
                source = Path(path)
                if source.is_file():
                    rel = f"sweeps/{sweep.name}/run-{r.index}/{source.name}"
                    self._files[rel] = OutFile(file_digest(source), source=source)
                    files[kind] = source.name
            self.clips[sweep.name][r.index] = files

    def files(self) -> dict[str, OutFile]:
        return dict(self._files)

    # -- pages -------------------------------------------------------------------------------
    def pages(self, strings: dict[str, str]) -> list[PageInput]:
        section = self.sims.section.strip("/") or "gallery"
        out = []
        for n, sweep in enumerate(self.sims.sweeps):
            rel = PurePosixPath(section, f"sweep-{sweep.name}.md")
            root = "../" * (len(rel.parts) - 1)
            view = self.view(sweep, root)
            body = self.partials.render("sweep", sweep=view)
            toc = [{"id": a, "title": t, "children": []} for a, t in view["toc"]]
            out.append(
                PageInput(
                    rel,
                    {"title": view["title"], "weight": 95 + n},
                    "",
                    False,
                    None,
                    f"sweep-{sweep.name}",
                    body_html=body,
                    toc=toc,
                    digest=hashlib.sha256(body.encode()).hexdigest(),
                )
            )
        return out

    def view(self, sweep: SweepConfig, root: str) -> dict[str, Any]:
        """What ``partials/sweep.html`` shows (plain data; the partial escapes it)."""
        from sims.sweeps import results

        w = self.words
        base = root + url_quote(f"sweeps/{sweep.name}/")
        view: dict[str, Any] = {
            "title": sweep.title or sweep.name,
            "script": self._relative(sweep.script),
            "scene": sweep.scene,
            "words": w,
            "error": self.failed.get(sweep.name),
            "toc": [],
            "sort_js": root + "assets/sweep.js",
            "summary": "",
            "header": None,
        }
        records = self.records.get(sweep.name)
        if records is None:
            return view
        failed = sum(1 for r in records if not r.ok)
        view["summary"] = f"{len(records)} {w['runs']}, {failed} {w['failed']}"
        view["downloads"] = [
            {"href": base + results.CSV_NAME, "label": results.CSV_NAME},
            {"href": base + results.JSONL_NAME, "label": results.JSONL_NAME},
        ]
        best = best_runs(records, sweep)
        view["key"] = sweep.key
        view["best"] = [self._best_view(sweep, r, base) for r in best]
        header, rows = results.table(records)
        if sweep.key:
            order = {r.index: i for i, r in enumerate(_ranked(records, sweep))}
            rows.sort(key=lambda row: order.get(int(row[0]), len(order)))
        view["header"], view["rows"] = header, rows[:TABLE_ROWS]
        view["truncated"] = (
            w["shown"].format(n=TABLE_ROWS, key=sweep.key or "index")
            if len(rows) > TABLE_ROWS
            else ""
        )
        points = []
        for r in records:
            x, y = key_value(r, sweep.x), key_value(r, sweep.y)
            if x is not None and y is not None:
                points.append((r.index, x, y))
        best_ids = {r.index for r in best}
        view["scatter"] = trusted(scatter(points, best_ids, w["where"], sweep.x, sweep.y))
        values = [v for v in (key_value(r, sweep.key) for r in records if r.ok) if v is not None]
        title = f"{w['spread']} {sweep.key}"
        counts = w["runs"].strip()
        view["histogram"] = (
            trusted(histogram(values, title, sweep.key or "", counts)) if values else ""
        )
        view["plots_title"] = f"{sweep.x} / {sweep.y}"
        view["toc"] = [("sweep-plots", view["plots_title"]), ("sweep-runs", w["table"])]
        if view["best"]:
            view["toc"].insert(0, ("sweep-best", f"{w['best']} {sweep.key}"))
        return view

    def _best_view(self, sweep: SweepConfig, r: Any, base: str) -> dict[str, Any]:
        files = self.clips.get(sweep.name, {}).get(r.index, {})
        run_base = base + url_quote(f"run-{r.index}/")
        return {
            "index": r.index,
            "seed": r.seed,
            "value": key_value(r, sweep.key),
            "args": ", ".join(f"{k}={v}" for k, v in r.args.items()),
            "video": run_base + files["video"] if "video" in files else None,
            "poster": run_base + files["poster"] if "poster" in files else None,
            "width": self.sims.width,
            "height": self.sims.height,
        }


class _NotYet(Exception):
    """The sweep is not in the cache and this build runs nothing (BuildOptions.render_clips)."""


def _ranked(records: list[Any], sweep: SweepConfig) -> list[Any]:
    everyone = SweepConfig(**{**sweep.__dict__, "best": len(records)})
    return best_runs(records, everyone)


def _clip_args(record: Any) -> dict[str, Any]:
    """A run's arguments for its clip, where the script clip source takes them."""
    from sims.remote_api.script_clips import PARAMS

    if not record.args or "args" not in PARAMS:
        return {}
    return {"args": [f"--{k}={v}" for k, v in record.args.items() if k != "seed"]}
