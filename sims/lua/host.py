"""A scene's child and customization scripts, run the way CoppeliaSim's main script runs them.

``ScriptHost(world)`` loads every enabled, non-empty child and customization script of the
World's scene, each in its own sandboxed Lua state (runtime.py; the ``sim.*`` functions and
constants are bound to it on first use: binding.py). Per simulation pass (the
scene's time step, 50 ms by default; several physics steps of the World):

1. actuation: threaded scripts resume (launched at the first pass; they run until they yield at
   ``sim.switchThread``/``sim.wait`` or an automatic switch), then non-threaded child scripts
   (``sysCall_actuation``, or the whole old-style chunk with ``sim_call_type`` = actuation),
   then customization scripts;
2. the World's physics steps;
3. sensing: the same order with ``sysCall_sensing`` / the sensing call type.

``start()`` runs initialisation (customization scripts first, then child scripts) and the first
actuation; ``stop()`` runs cleanup. The host follows the World through ``add_step_hook``: a pass
ends every ``steps_per_pass`` physics steps; an unstarted host starts at the first step.

A script error is recorded once (``errors``) and the run goes on, as in CoppeliaSim; a call of
a function the emulation lacks is recorded once per script line (``missing``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .binding import Binder, LuaCaller
from .constants import constants
from .runtime import LuaScriptError, LuaState, run_tmp_dir


@dataclass(frozen=True)
class Unemulated:
    """A call of a function this emulation does not provide."""

    function: str
    scene: str
    script: str
    line: int

    def describe(self) -> str:
        return f"{self.scene}: script {self.script!r} line {self.line}: {self.function}"


@dataclass
class ScriptRun:
    """One script and its Lua state."""

    name: str
    kind: str  # "child" or "customization"
    threaded: bool
    object: int  # World handle of the object it is attached to
    handle: int
    text: str
    state: Any = None
    chunk: Any = None
    new_style: bool = False
    co: Any = None
    finished: bool = False
    removed: bool = False
    executions: int = 0
    switch_ms: int = 2
    auto_switch: bool = True
    active: bool = True  # a customization script called during simulation
    callbacks: dict[str, Any] = field(default_factory=dict)  # sysCall_* looked up once
    threadmain: bool = False  # a 4.x threaded script: sysCall_threadmain is the coroutine


class ScriptHost:
    """The scripts of one World's scene; see the module docstring."""

    def __init__(
        self,
        world: Any,
        *,
        signals: dict[str, dict[str, Any]] | None = None,
        pass_dt: float | None = None,
        status: Callable[[str], None] | None = None,
        scene_label: str | None = None,
        customization: bool = True,
        enabled: bool = True,
    ):
        self.world = world
        source = getattr(world, "source", None)
        self.scene = scene_label or Path(str(getattr(source, "source", "") or "scene")).name
        self.new_api = str(getattr(source, "version", "")).find("CoppeliaSim 4") >= 0
        self.signals = signals if signals is not None else {"float": {}, "int": {}, "string": {}}
        dt = pass_dt or getattr(source, "time_step", 0.05) or 0.05
        self.steps_per_pass = max(1, round(dt / world.timestep))
        self.pass_dt = self.steps_per_pass * world.timestep
        self._sync_sensing()
        self._status = status
        self.ports: list[int] = []
        self.stop_requested = False  # a script called sim.stopSimulation
        self.clock: Callable[[], float] | None = None  # the run's clock (sim.getSystemTime)
        self.scene_dir = _scene_dir(source)
        self.errors: list[str] = []
        self.missing: list[Unemulated] = []
        self.statusbar: list[str] = []
        self.enabled = enabled
        self.on_missing: Callable[[Unemulated], None] | None = None
        self._call_types: dict[tuple[str, str], int] = {}
        self.started = False
        self.passes = 0
        self._steps_seen = 0
        self._tmp = run_tmp_dir()  # stale ones of killed runs removed first (runtime.py)
        self.scripts = self._collect(source, customization) if enabled else []
        self._remove_hook = world.add_step_hook(self.on_step)

    # -- scripts -------------------------------------------------------------------------------
    def _collect(self, source: Any, customization: bool) -> list[ScriptRun]:
        runs: list[ScriptRun] = []
        by_handle = {o.handle: o for o in getattr(source, "objects", ())}
        kinds = ("child", "customization") if customization else ("child",)
        for script in getattr(source, "scripts", ()):
            if script.kind not in kinds or script.disabled or not script.text.strip():
                continue
            obj = by_handle.get(script.object)
            name = obj.name if obj is not None else f"script{len(runs) + 1}"
            handle = self.world.handle(obj.name) if obj is not None else None
            label = name if script.kind == "child" else f"{name} (customization)"
            runs.append(
                ScriptRun(
                    label, script.kind, script.threaded, handle or -1, len(runs) + 1, script.text
                )
            )
        return runs

    def _load(self, run: ScriptRun) -> None:
        state = LuaState(
            self._tmp.name,
            lambda name, line, r=run: self._note_missing(r, name, line),
            modules=self.scene_dir,
        )
        run.state = state
        Binder(state, LuaCaller(self, run), run.threaded, self.new_api).install()
        run.chunk = state.compile(run.text, run.name)

    def _note_missing(self, run: ScriptRun, name: str, line: int) -> None:
        item = Unemulated(name, self.scene, run.name, line)
        if item not in self.missing:
            self.missing.append(item)
            if self.on_missing is not None:
                self.on_missing(item)

    def _error(self, run: ScriptRun, exc: Exception) -> None:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        message = f"{self.scene}: {first}"
        run.removed = True  # CoppeliaSim disables a script that raised; the rest runs on
        if message not in self.errors:
            self.errors.append(message)
            self.status(f"Lua runtime error: {first}")

    # -- dispatch ------------------------------------------------------------------------------
    def _call_type(self, run: ScriptRun, phase: str) -> int:
        key = (run.kind, phase)
        if key not in self._call_types:
            self._call_types[key] = self._lookup_call_type(run, phase)
        return self._call_types[key]

    def _lookup_call_type(self, run: ScriptRun, phase: str) -> int:
        table = constants(self.new_api)
        prefix = "childscriptcall_" if run.kind == "child" else "customizationscriptcall_"
        names = {
            "init": "initialization",
            "cleanup": "cleanup",
            "actuation": "actuation" if run.kind == "child" else "simulationactuation",
            "sensing": "sensing" if run.kind == "child" else "simulationsensing",
            "before": "lastbeforesimulation",
        }
        return table[prefix + names[phase]]

    def _dispatch(self, run: ScriptRun, phase: str) -> None:
        if run.removed or run.state is None:
            return
        if not run.active and phase in ("actuation", "sensing"):
            return
        callback = {
            "init": "sysCall_init",
            "cleanup": "sysCall_cleanup",
            "actuation": "sysCall_actuation",
            "sensing": "sysCall_sensing",
            "before": "sysCall_beforeSimulation",
        }[phase]
        try:
            if run.new_style:
                if callback not in run.callbacks:
                    run.callbacks[callback] = run.state.get(callback)
                fn = run.callbacks[callback]
                if fn is not None:
                    run.state.call(fn)
            elif not run.threaded:
                run.state.section(run.chunk, self._call_type(run, phase))
                run.executions += 1
        except LuaScriptError as exc:
            self._error(run, exc)

    def _init(self, run: ScriptRun) -> None:
        try:
            self._load(run)
            if run.threaded:
                run.state.set("sim_call_type", constants(self.new_api)["childscriptcall_threaded"])
                return
            run.state.set("sim_call_type", self._call_type(run, "init"))
            run.state.call(run.chunk)
            run.executions += 1
            run.new_style = any(
                run.state.get(n) is not None
                for n in ("sysCall_init", "sysCall_actuation", "sysCall_sensing", "sysCall_cleanup")
            )
            if run.new_style:
                self._dispatch(run, "init")
        except LuaScriptError as exc:
            self._error(run, exc)

    def _resume(self, run: ScriptRun) -> None:
        if not run.threaded or run.finished or run.removed or run.state is None:
            return
        try:
            if run.co is None:
                run.co = run.state.thread(run.chunk)
            if run.state.resume(run.co) == "dead":
                main = None if run.threadmain else run.state.get("sysCall_threadmain")
                if main is None:
                    run.finished = True
                    return
                # a 4.x threaded script: its chunk defined sysCall_threadmain, which runs as
                # the coroutine from now on (CoppeliaSim 4.2+ converts such scripts so)
                run.threadmain = True
                run.new_style = True
                run.co = run.state.thread(main)
                if run.state.resume(run.co) == "dead":
                    run.finished = True
        except LuaScriptError as exc:
            run.finished = True
            self._error(run, exc)

    def _ordered(self) -> list[ScriptRun]:
        return [r for r in self.scripts if r.kind == "child"] + [
            r for r in self.scripts if r.kind == "customization"
        ]

    def start(self) -> None:
        """Initialise every script and run the first actuation (simulation start)."""
        if self.started:
            return
        self.started = True
        customs = [r for r in self.scripts if r.kind == "customization"]
        for run in customs:
            self._init(run)
            self._dispatch(run, "before")
        for run in self.scripts:
            if run.kind == "child":
                self._init(run)
        self._joint_callbacks()
        self.actuation()

    def _joint_callbacks(self) -> None:
        """Joints whose script defines ``sysCall_jointCallback`` are controlled by it: called
        at every physics step with the joint's state, its answer (velocity, force) drives the
        joint's motor, as CoppeliaSim's custom joint control does."""
        runs = [
            r
            for r in self.scripts
            if r.new_style and r.state is not None and r.object > 0
            and self.world.is_joint(r.object) and r.state.get("sysCall_jointCallback") is not None
        ]  # fmt: skip
        if not runs:
            return
        setter = getattr(self.world, "set_joint_callback", None)
        if setter is not None:  # the World calls it before each physics step (mech's)
            for run in runs:
                setter(run.object, lambda data, r=run: self._joint_answer(r, data))
            self._remove_joint_hook = lambda: [setter(r.object, None) for r in runs]
            return
        passes = {r.handle: 0 for r in runs}

        def control(world: Any) -> None:
            for run in runs:
                if run.removed or run.state is None:
                    continue
                self._joint_callback(run, passes[run.handle])
                passes[run.handle] += 1

        self._remove_joint_hook = self.world.add_step_hook(control)

    def _joint_answer(self, run: ScriptRun, data: dict) -> dict | None:
        """The script's ``sysCall_jointCallback(inData)`` answer, as a dict (None: no answer,
        or the script is disabled)."""
        from .runtime import to_py

        if run.removed or run.state is None:
            return None
        try:
            out = run.state.call(run.state.get("sysCall_jointCallback"), data)
        except LuaScriptError as exc:
            self._error(run, exc)
            return None
        result = to_py(out[0]) if out else None
        return result if isinstance(result, dict) else None

    def _joint_callback(self, run: ScriptRun, count: int) -> None:
        w = self.world
        h = run.object
        j = w.joint(h)
        command = w.motor_command(h)
        pos = w.joint_position(h)
        target = command[1] if command and command[0] == "position" else pos
        low = j.lower if j.lower is not None else -3.141592653589793
        high = j.upper if j.upper is not None else 3.141592653589793
        data = {
            "first": count == 0, "passCnt": count, "totalPasses": 1, "handle": h,
            "revolute": j.kind == "revolute", "cyclic": j.lower is None,
            "lowLimit": low, "highLimit": high, "currentPos": pos,
            "currentVel": w.joint_velocity(h), "targetPos": target, "errorValue": target - pos,
            "effort": 0.0, "dynStepSize": w.timestep,
            "velUpperLimit": j.max_velocity if j.max_velocity else 1e9, "maxForce": j.max_force,
        }  # fmt: skip
        try:
            out = run.state.call(run.state.get("sysCall_jointCallback"), data)
        except LuaScriptError as exc:
            self._error(run, exc)
            return
        from .runtime import to_py

        result = to_py(out[0]) if out else None
        if isinstance(result, dict):
            force = result.get("force")
            if isinstance(force, (int, float)) and abs(force) != j.max_force:
                w.set_joint_max_force(h, abs(float(force)))
            velocity = result.get("velocity")
            if isinstance(velocity, (int, float)):
                w.set_joint_target_velocity(h, float(velocity))

    def actuation(self) -> None:
        for run in self.scripts:
            if run.threaded:
                self._resume(run)
        for run in self._ordered():
            if not run.threaded:
                self._dispatch(run, "actuation")
        # what CoppeliaSim's default main script does next: IK groups, paths... (the World's)
        main = getattr(self.world, "main_script_actuation", None)
        if main is not None:
            main(self.pass_dt)

    def sensing(self) -> None:
        for run in self._ordered():
            if not run.threaded:
                self._dispatch(run, "sensing")

    def _sync_sensing(self) -> None:
        """The World handles its proximity sensors (sensors="main-script") at the end of this
        host's passes, as CoppeliaSim's main script does before the child scripts' sensing."""
        sensors = getattr(self.world, "proximity_sensors", None)
        if sensors is not None and sensors.pass_steps != self.steps_per_pass:
            sensors.pass_steps = self.steps_per_pass

    def on_step(self, world: Any) -> None:
        if world.steps == 1:  # a (re)started world has new sensors
            self._sync_sensing()
        if not self.started:
            self._steps_seen = world.steps - 1
            self.start()
        if world.steps < self._steps_seen:  # the world was reset without a stop: start again
            self._steps_seen = 0
        self._steps_seen = world.steps
        if world.steps % self.steps_per_pass == 0:
            self.passes += 1
            self.sensing()
            self.actuation()

    def stop(self) -> None:
        """Cleanup calls (simulation stop); the scripts' states are dropped, as in CoppeliaSim."""
        if not self.started:
            return
        for run in self._ordered():
            if not run.threaded or run.new_style:
                self._dispatch(run, "cleanup")
        for run in self.scripts:
            run.state = run.chunk = run.co = None
            run.callbacks.clear()
            run.finished = run.removed = run.new_style = run.threadmain = False
            run.active = True
            run.auto_switch = True
            run.executions = 0
        self.started = False
        self.stop_requested = False
        remove = getattr(self, "_remove_joint_hook", None)
        if remove is not None:
            remove()
            self._remove_joint_hook = None

    def close(self) -> None:
        self.stop()
        self._remove_hook()
        self._tmp.cleanup()

    # -- what the sim.* functions need ---------------------------------------------------------
    @property
    def time(self) -> float:
        return float(self.world.time)

    def state_code(self) -> int:
        return 0x11 if self.started else 0x00

    def status(self, message: str) -> None:
        self.statusbar.append(message)
        if self._status is not None:
            self._status(message)

    def serve(self, port: int) -> None:
        if port not in self.ports:
            self.ports.append(port)

    def system_time(self) -> float:
        """The run's clock (virtual unless the run is in real time); the simulation time when
        the scripts run on their own."""
        return self.clock() if self.clock is not None else self.time

    def script_by_handle(self, handle: int) -> ScriptRun | None:
        return next((r for r in self.scripts if r.handle == handle), None)

    def script_of_object(self, handle: int, kind: str = "child") -> ScriptRun | None:
        return next((r for r in self.scripts if r.object == handle and r.kind == kind), None)

    def script_named(self, name: str, kind: str = "child") -> ScriptRun | None:
        """The script attached to the object ``name`` (``name#``/``name#0`` too)."""
        base = name.split("#")[0] if name.endswith(("#", "#0")) else name
        h = self.world.find(base)
        for run in self.scripts:
            if run.kind == kind and (run.object == h or run.name.split(" (")[0] == base):
                return run
        return None

    def call_function(self, script: str, kind: str, function: str, args: tuple) -> tuple:
        """Call a script's Lua function (simxCallScriptFunction); raises LookupError or
        LuaScriptError. Returns its results converted to Python."""
        if not self.started:
            self.start()
        run = self.script_named(script, kind)
        if run is None or run.state is None:
            raise LookupError(f"no {kind} script attached to {script!r} is running")
        return self.call_run(run, function, args)

    def call_run(self, run: ScriptRun, function: str, args: tuple) -> tuple:
        """Call a function of a running script; its results converted to Python."""
        from .runtime import to_py

        fn = run.state.get(function)
        if fn is None:
            raise LookupError(f"script {run.name!r} has no function {function!r}")
        out = run.state.call(fn, *args)
        return tuple(to_py(v) for v in out)

    def report(self) -> list[str]:
        """The end-of-run lines: script errors, then functions not emulated."""
        lines = [f"[lua] script error: {e}" for e in self.errors]
        if self.missing:
            lines.append("[lua] functions the scene's scripts called that are not emulated:")
            lines += [f"  {m.describe()}" for m in self.missing]
        return lines


def _scene_dir(source: Any) -> str | None:
    """The folder of the scene file: ``require`` finds Lua modules beside it (only there)."""
    path = str(getattr(source, "source", "") or "")
    if not path:
        return None
    folder = Path(path).resolve().parent
    return str(folder) if folder.is_dir() else None
