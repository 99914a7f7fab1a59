"""Sampling a running World at a fixed rate: the data behind every clip, CSV and plot.

A :class:`Recorder` hooks into ``World.step`` and, every ``1/fps`` simulated seconds of *clip
time*, stores one sample (time, body pose, heading, joint angles or wheel speeds, extra values
the scenario set) and hands the World to ``on_frame`` (the clip renderer). Clip time counts
physics steps since recording began, so it keeps running across ``World.reset()``.

Once ``frames`` samples are taken, a step past the clip's end time (``frames / fps``) raises
:class:`StopRecording`, which ends the driving code wherever it is (so a driver that stops
exactly at the end still gets to note its final readings); a wall-clock ``deadline`` raises
:class:`RecordingTimeout`. Both derive from BaseException so a scenario's ``except Exception``
cannot swallow them.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sims.world import World

FrameSink = Callable[[World], None]


@dataclass
class RecordingPlan:
    """Everything needed to key, run and describe one clip; built in parent and worker alike.

    ``hash_files`` are the files whose bytes identify this source's behaviour (the scenario
    file, a course script...); the engine's own files are added by sims.clip_cache.
    ``drive(world, record)`` runs inside a started Recorder and may simply return early.
    ``measure``: for a source whose length is only known by running it (a course script
    without ``seconds``), the dry run that finds it; :meth:`length` calls it once, when a clip
    is actually rendered, so building a key (every build, cached or not) runs nothing.
    """

    scene: str
    seed: int
    duration: float
    description: str
    source_path: str
    params: dict[str, Any]
    hash_files: list[str]
    drive: Callable[[World, Recorder], None]
    scene_options: dict[str, Any] = field(default_factory=dict)
    follow: str | None = None
    joints: tuple[str, ...] = ()
    joint_quantity: str = "angle"
    extra_columns: tuple[str, ...] = ()
    measure: Callable[[], float] | None = None

    def length(self, seconds: float | None = None) -> float:
        """The clip's simulated length: ``seconds`` when given, else the plan's duration
        (measured now, once, if the plan has a ``measure``)."""
        if seconds is not None:
            return seconds
        if self.measure is not None:
            self.duration, self.measure = float(self.measure()), None
        return self.duration

    @property
    def length_known(self) -> bool:
        """Whether :meth:`length` is known without running the source."""
        return self.measure is None


class StopRecording(BaseException):
    """The clip is complete; unwinds the driving code."""


class RecordingTimeout(BaseException):
    """The wall-clock time limit passed while the driving code was running."""


def _decimals(column: str) -> int:
    if column == "t":
        return 3
    if column.endswith("_deg"):
        return 2
    if column.endswith("_rad_s"):
        return 3
    return 4


def _fmt(value: float | None, decimals: int) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    text = f"{value:.{decimals}f}"
    return "0." + "0" * decimals if text.lstrip("-").strip("0.") == "" else text


@dataclass
class Recording:
    """Samples of one run: ``columns`` name each value of a row. Floats are rounded on output."""

    columns: list[str]
    rows: list[list[float | None]] = field(default_factory=list)
    events: list[dict[str, Any]] = field(default_factory=list)
    breaks: list[int] = field(default_factory=list)  # row indices where a World.reset() began a run
    subject: str = ""  # the object whose pose is recorded

    def column(self, name: str) -> list[float | None]:
        i = self.columns.index(name)
        return [row[i] for row in self.rows]

    def rounded_rows(self) -> list[list[str]]:
        dec = [_decimals(c) for c in self.columns]
        return [[_fmt(v, d) for v, d in zip(row, dec, strict=True)] for row in self.rows]

    def to_csv(self) -> str:
        lines = [",".join(self.columns)] + [",".join(r) for r in self.rounded_rows()]
        return "\n".join(lines) + "\n"

    def to_dict(self) -> dict[str, Any]:
        rows = [[None if v == "" else float(v) for v in r] for r in self.rounded_rows()]
        return {
            "subject": self.subject,
            "columns": self.columns,
            "samples": rows,
            "events": self.events,
            "run_starts": self.breaks,
        }

    def to_json(self, **extra: Any) -> str:
        data = {**extra, **self.to_dict()}
        return json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=False) + "\n"


class Recorder:
    """Samples ``world`` at ``fps`` for ``frames`` samples; scenarios get it as ``record``."""

    def __init__(
        self,
        world: World,
        *,
        fps: float,
        frames: int,
        follow: str | None = None,
        joints: tuple[str, ...] = (),
        quantity: str = "angle",
        extra_columns: tuple[str, ...] = (),
        on_frame: FrameSink | None = None,
        deadline: float | None = None,
        film_every: float = 1.0,
        on_sample: FrameSink | None = None,
    ):
        """``film_every``: a time-lapse films every n-th sample (``speed``), data keep all.
        ``on_sample``: called at every data sample and once more at the clip's end time (a
        replay's keyframes: sims/replay/export.py), so it sees ``frames + 1`` states."""
        if film_every < 1:
            raise ValueError(f"speed must be at least 1, not {film_every!r}")
        if quantity not in ("angle", "speed"):
            raise ValueError(f"quantity must be 'angle' or 'speed', not {quantity!r}")
        self.world = world
        self.fps = fps
        self.frames = frames
        self.follow = follow or world.model.robot
        self.joints = joints
        self.quantity = quantity
        self.on_frame = on_frame
        self.deadline = deadline
        self.film_every = film_every
        self.on_sample = on_sample
        self.ended = on_sample is None  # the end state was handed to on_sample
        self.filmed = 0
        unit = "_deg" if quantity == "angle" else "_rad_s"
        columns = ["t", "x", "y", "z", "alpha_deg", "beta_deg", "gamma_deg", "heading_deg"]
        columns += [j + unit for j in joints]
        self.recording = Recording(columns + list(extra_columns), subject=self.follow)
        self._extra: dict[str, float | None] = {c: None for c in extra_columns}
        self._clip_steps = 0
        self._next_frame = 0
        self._remove_hook: Callable[[], None] | None = None
        self._world_steps = world.steps
        self.done = False

    @property
    def time(self) -> float:
        """Clip time (s): physics steps since recording began, across resets."""
        return self._clip_steps * self.world.timestep

    @property
    def taken(self) -> int:
        return len(self.recording.rows)

    def set(self, column: str, value: float | None) -> None:
        """Set an extra column's value for the following samples (declared by the scenario)."""
        if column not in self._extra:
            raise KeyError(f"undeclared extra column {column!r}")
        self._extra[column] = value

    def note(self, text: str, **data: Any) -> None:
        """A timestamped event (targets reached, keys pressed) kept in the JSON output."""
        self.recording.events.append({"t": round(self.time, 3), "text": text, **data})

    def start(self) -> None:
        self._remove_hook = self.world.add_step_hook(self._after_step)
        self._capture()

    def finish(self) -> Recording:
        """Idle the world until every frame is taken (short drivers) and, with ``on_sample``,
        the end time is reached; then unhook."""
        try:
            while not (self.done and self.ended):
                self.world.step()
        except StopRecording:
            pass
        if self._remove_hook is not None:
            self._remove_hook()
            self._remove_hook = None
        return self.recording

    def _after_step(self, world: World) -> None:
        if self.done and self._clip_steps >= self._next_frame:
            raise StopRecording  # a step past the clip's end: the driver may stop exactly at it
        self._clip_steps += 1
        if world.steps < self._world_steps:  # the world was reset since the last step
            self.recording.breaks.append(self.taken)
            self.note("world reset")
        self._world_steps = world.steps
        if not self.done and self._clip_steps >= self._next_frame:
            self._capture()
        elif self.done and not self.ended and self._clip_steps >= self._next_frame:
            self.ended = True  # the clip's end time: the last state of a replay
            assert self.on_sample is not None
            self.on_sample(world)

    def _capture(self) -> None:
        if self.deadline is not None and time.monotonic() > self.deadline:
            raise RecordingTimeout(f"time limit passed at clip time {self.time:.2f} s")
        w = self.world
        (x, y, z), _ = w.object_pose(self.follow)
        euler = [math.degrees(a) for a in w.object_orientation(self.follow)]
        row: list[float | None] = [self.time, x, y, z, *euler, math.degrees(w.heading(self.follow))]
        for j in self.joints:
            row.append(
                math.degrees(w.joint_position(j))
                if self.quantity == "angle"
                else w.joint_velocity(j)
            )
        row += list(self._extra.values())
        self.recording.rows.append(row)
        if self.on_sample is not None:
            self.on_sample(w)
        if self.taken - 1 == round(self.filmed * self.film_every):
            self.filmed += 1
            if self.on_frame is not None:
                self.on_frame(w)
        n = self.taken
        self._next_frame = round(n / (self.fps * w.timestep))
        if n >= self.frames:
            self.done = True


def drive(world: World, recorder: Recorder, run: Callable[[World, Recorder], None]) -> Recording:
    """Run a driver under a recorder; a complete clip ends the driver early."""
    recorder.start()
    try:
        run(world, recorder)
    except StopRecording:
        pass
    return recorder.finish()


def record(
    plan: RecordingPlan,
    *,
    fps: float,
    seconds: float | None = None,
    on_frame: FrameSink | None = None,
    deadline: float | None = None,
    render_with: str | None = None,
    speed: float = 1.0,
    on_sample: FrameSink | None = None,
) -> tuple[Recording, str]:
    """Run ``plan`` in a fresh World for ``seconds`` (default: its duration) at ``fps``.

    The one place a plan meets a World: clips (with ``on_frame`` filming) and run_scenario
    (data only) both come through here. Returns the samples and the renderer that ran.
    ``speed``: time-lapse factor; samples stay at ``fps``, ``on_frame`` sees every
    ``speed``-th one (:func:`frame_count` of them); ``on_sample`` sees every sample and the
    end state (a replay).
    """
    length = plan.length(seconds)
    with World(plan.scene, seed=plan.seed, render_with=render_with, **plan.scene_options) as world:
        recorder = Recorder(
            world,
            fps=fps,
            frames=sample_count(length, fps),
            follow=plan.follow,
            joints=plan.joints,
            quantity=plan.joint_quantity,
            extra_columns=plan.extra_columns,
            on_frame=on_frame,
            deadline=deadline,
            film_every=speed,
            on_sample=on_sample,
        )
        return drive(world, recorder, plan.drive), world.renderer


def sample_count(seconds: float, fps: float) -> int:
    """Data samples (CSV rows) of a clip ``seconds`` long: one every ``1/fps`` simulated s."""
    return max(1, round(seconds * fps))


def frame_count(seconds: float, fps: float, speed: float = 1.0) -> int:
    """Video frames of a clip: samples 0, speed, 2·speed... (rounded) of ``sample_count``."""
    samples = sample_count(seconds, fps)
    frames = 0
    while round(frames * speed) < samples:
        frames += 1
    return frames
