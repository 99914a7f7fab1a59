"""Many runs of one remote API script: the Python entry points of sweeps and searches.

``evaluate(script, scene, batch, executor=...)`` is for a user's optimiser: a genetic
algorithm hands it a population (a list of dicts of arguments) and gets one
:class:`~sims.sweeps.one_run.RunRecord` per candidate back, in the batch's order, the runs
spread over local worker processes or a Ray cluster. ``sweep(...)`` runs a planned sweep and
writes results.csv and results.jsonl (sims/sweeps/results.py); ``sitegen remote-api sweep`` and
the gallery's ``sims: sweeps:`` use it. Every run is isolated as ``remote-api run`` isolates
one (sims/sweeps/one_run.py), and a run's record depends only on the script, the scene, its
seed and its arguments, never on the executor or the number of workers.

Why not a home-made distributed engine: past one machine, runs go to Ray (retries on a lost
worker or node, cluster launchers, KubeRay); on one machine, the clip workers' pool
(sims/clip_pool.py) already does what is needed with nothing to install.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from sims.sweeps import results as results_files
from sims.sweeps.one_run import RunRecord, RunSettings
from sims.sweeps.plan import SEED_NAME, RunSpec, derived_seed
from sims.sweeps.progress import SweepProgress

DEFAULT_TIMEOUT = 300.0
EXECUTORS = ("local", "ray")


class Executor(Protocol):
    """Runs jobs, yields each record (a dict) as its run ends, in any order."""

    name: str

    def describe(self) -> str: ...

    def run(self, jobs: list[dict[str, Any]], started: Callable[[int], None] | None = None): ...

    def close(self) -> None: ...

    def __enter__(self) -> Executor: ...

    def __exit__(self, *exc: object) -> None: ...


def make_executor(
    executor: str | Executor | None = "local",
    workers: int | None = None,
    address: str | None = None,
    retries: int | None = None,
) -> Executor:
    """ "local" (``workers`` processes, default every core), "ray" (the cluster at
    ``address``: "auto" for a running one; none: the one this process joined, else a new local
    one) or an executor object, returned as is."""
    if executor is None:
        executor = "local"
    if not isinstance(executor, str):
        return executor
    if executor == "local":
        from sims.sweeps.local import LocalExecutor

        return LocalExecutor(workers, **({"retries": retries} if retries is not None else {}))
    if executor == "ray":
        from sims.sweeps.ray_runs import RayExecutor, import_ray

        import_ray()  # one clear line now, not at the first run, when Ray is missing
        return RayExecutor(address, **({"retries": retries} if retries is not None else {}))
    raise ValueError(f"unknown executor {executor!r} (known: {', '.join(EXECUTORS)})")


@dataclass(frozen=True)
class SweepOutcome:
    records: list[RunRecord]
    csv: Path | None
    jsonl: Path | None
    executor: str  # what ran it (describe())
    wall_seconds: float

    @property
    def failed(self) -> list[RunRecord]:
        return [r for r in self.records if not r.ok]


def settings_for(
    script: str | Path,
    scene: str,
    *,
    seconds: float | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    after: float = 0.0,
    server: str | None = None,
    cwd: str | Path | None = None,
    label: str | None = None,
) -> RunSettings:
    """What every run shares; a scene file is made absolute so every worker finds it."""
    from sims.scene.resolve import is_bundled

    path = Path(script).resolve()
    if not is_bundled(scene):
        scene = str(Path(scene).resolve())
    return RunSettings(
        script=str(path),
        label=label or str(script),
        scene=scene,
        seconds=seconds,
        timeout=timeout,
        after=after,
        server=server,
        cwd=str(Path(cwd).resolve()) if cwd else str(Path.cwd()),
    )


def run_all(
    settings: RunSettings,
    runs: Sequence[RunSpec],
    executor: Executor,
    progress: SweepProgress | None = None,
    got: dict[int, RunRecord] | None = None,
) -> list[RunRecord]:
    """Every run on ``executor``; records in run-index order. ``got`` fills as runs end (what
    a caller still has when the sweep is interrupted)."""
    jobs = [settings.job(run) for run in runs]
    got = {} if got is None else got
    started = progress.started if progress is not None else None
    for record in executor.run(jobs, started):
        got[record["index"]] = RunRecord.from_json(record)
        if progress is not None:
            progress.finished(record)
    return [got[run.index] for run in runs]


def sweep(
    settings: RunSettings,
    runs: Sequence[RunSpec],
    out_dir: str | Path | None,
    executor: str | Executor | None = "local",
    *,
    workers: int | None = None,
    address: str | None = None,
    progress: SweepProgress | None = None,
) -> SweepOutcome:
    """Run a planned sweep and write results.csv/results.jsonl into ``out_dir`` (if given).
    ``executor``: a name (made and closed here) or an executor object (left open)."""
    import time

    chosen = make_executor(executor, workers, address)
    started = time.monotonic()
    ended: dict[int, RunRecord] = {}
    try:
        described = chosen.describe()
        records = run_all(settings, runs, chosen, progress, ended)
    except KeyboardInterrupt:  # the rows of the runs that ended are kept
        if out_dir is not None and ended:
            results_files.write(Path(out_dir), list(ended.values()))
        raise
    finally:
        if chosen is not executor:  # an executor the caller made is the caller's to close
            chosen.close()
    csv_path = jsonl_path = None
    if out_dir is not None:
        csv_path, jsonl_path = results_files.write(Path(out_dir), records)
    return SweepOutcome(records, csv_path, jsonl_path, described, time.monotonic() - started)


def candidates(batch: Sequence[Mapping[str, Any]], sweep_seed: int = 0) -> list[RunSpec]:
    """A batch of argument dicts as runs: values become text (``--NAME=VALUE``); a ``seed``
    key gives the run's seed, else it comes from ``sweep_seed`` and the candidate's index."""
    runs = []
    for index, candidate in enumerate(batch):
        args = tuple((str(k), _text(v)) for k, v in candidate.items())
        seed = (
            int(candidate[SEED_NAME]) if SEED_NAME in candidate else derived_seed(sweep_seed, index)
        )
        runs.append(RunSpec(index, seed, args))
    return runs


def _text(value: Any) -> str:
    return repr(value) if isinstance(value, float) else str(value)


def evaluate(
    script: str | Path,
    scene: str,
    batch: Sequence[Mapping[str, Any]],
    executor: str | Executor | None = "local",
    *,
    workers: int | None = None,
    address: str | None = None,
    seconds: float | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    sweep_seed: int = 0,
    progress: bool = False,
) -> list[RunRecord]:
    """Run ``script`` once per candidate of ``batch`` and return the records in batch order.

    A record's ``results`` holds what the run reported (``RESULT key=value`` lines, the JSON
    file named by ``$SWEEP_RESULT_FILE``), ``final`` the robot's final pose and joints, and
    ``ok``/``status``/``error`` whether it ran to the end. Pass one executor object to several
    calls (``make_executor("ray", address="auto")``) to keep its workers between generations."""
    settings = settings_for(script, scene, seconds=seconds, timeout=timeout)
    runs = candidates(batch, sweep_seed)
    shown = SweepProgress(len(runs)) if progress else None
    chosen = make_executor(executor, workers, address)
    try:
        return run_all(settings, runs, chosen, shown)
    finally:
        if shown is not None:
            shown.close()
        if chosen is not executor:
            chosen.close()
