"""Jerk-limited motion profiles as CoppeliaSim computes them: Ruckig (``pip install ruckig``),
the library CoppeliaSim's own ``simRuckig`` plug-in wraps for ``sim.rmlPos``/``sim.ruckigPos``,
``sim.moveToConfig`` and ``sim.moveToPose``.

The plug-in (read in CoppeliaRobotics/simRuckig) runs Ruckig's online update every
``smallest_step`` (1e-4 s) with the output fed back as the next input, and a ``step(dt)`` of
the script advances ``dt / smallest_step`` updates; it finishes at the first update past the
trajectory's duration. Re-planning from a state on the trajectory gives the same trajectory, so
``Profile`` computes it once and samples it at those instants (``Trajectory.at_time``), which
costs one call per simulation pass instead of 500 (29,422 updates of 5.8 us for a 2.9 s
move, measured). Used by ``sims.simapi.motion`` and by whoever needs a profile (the legacy
API's helpers may too).
"""

from __future__ import annotations

from dataclasses import dataclass

from ruckig import ControlInterface, InputParameter, Result, Ruckig, Synchronization, Trajectory

#: flags of sim.ruckigPos / rmlPos: low bits choose the synchronisation
SYNC = {0: Synchronization.Phase, 1: Synchronization.Time, 2: Synchronization.Phase,
        3: Synchronization.No}  # fmt: skip
MIN_VEL, MIN_ACCEL = 0x100, 0x200
SMALLEST_STEP = 1e-4


class MotionError(ValueError):
    """Ruckig refused the input (limits that cannot be met, NaN...)."""


@dataclass
class Sample:
    result: int  # 0 moving, 1 reached
    position: list[float]
    velocity: list[float]
    acceleration: list[float]
    time_left: float


class Profile:
    """One multi-DoF profile from the current state to a target (position control) or to a
    target velocity (``velocity=True``), sampled by ``step(dt)``."""

    def __init__(
        self,
        position: list[float],
        velocity: list[float],
        acceleration: list[float],
        max_velocity: list[float],
        max_acceleration: list[float],
        max_jerk: list[float],
        target_position: list[float],
        target_velocity: list[float],
        *,
        flags: int = -1,
        selection: list[bool] | None = None,
        min_velocity: list[float] | None = None,
        min_acceleration: list[float] | None = None,
        velocity_control: bool = False,
        smallest_step: float = SMALLEST_STEP,
    ):
        n = len(position)
        self.dofs = n
        inp = InputParameter(n)
        inp.current_position = list(position)
        inp.current_velocity = list(velocity)
        inp.current_acceleration = list(acceleration)
        inp.target_position = list(target_position) if not velocity_control else list(position)
        inp.target_velocity = list(target_velocity)
        inp.target_acceleration = [0.0] * n
        inp.max_velocity = [abs(v) for v in max_velocity] if max_velocity else [1e9] * n
        inp.max_acceleration = [abs(v) for v in max_acceleration]
        inp.max_jerk = [abs(v) for v in max_jerk]
        if selection is not None:
            inp.enabled = [bool(s) for s in selection]
        if flags >= 0:
            inp.synchronization = SYNC[flags & 3]
        if min_velocity is not None:
            inp.min_velocity = list(min_velocity)
        if min_acceleration is not None:
            inp.min_acceleration = list(min_acceleration)
        if velocity_control:
            inp.control_interface = ControlInterface.Velocity
        self.trajectory = Trajectory(n)
        result = Ruckig(n).calculate(inp, self.trajectory)
        if result not in (Result.Working, Result.Finished):
            raise MotionError(f"the motion cannot be computed ({result.name})")
        self.duration = float(self.trajectory.duration)
        self.smallest = smallest_step
        self.updates = 0
        self.finished = False
        self._last: Sample | None = None

    def step(self, dt: float) -> Sample:
        """Advance ``dt`` seconds (a multiple of the smallest step, as the plug-in requires)."""
        if self.finished and self._last is not None:
            return Sample(1, *self._values(self.duration), time_left=self._last.time_left - dt)
        count = max(1, int(dt / self.smallest + 0.5))
        self.updates += count
        t = self.updates * self.smallest
        done = t > self.duration
        pos, vel, acc = self._values(min(t, self.duration))
        if self._last is None:
            left = self.duration - dt
        else:
            left = self._last.time_left - dt
        self.finished = done
        self._last = Sample(1 if done else 0, pos, vel, acc, left)
        return self._last

    def _values(self, t: float) -> tuple[list[float], list[float], list[float]]:
        p, v, a = self.trajectory.at_time(t)
        return [float(x) for x in p], [float(x) for x in v], [float(x) for x in a]
