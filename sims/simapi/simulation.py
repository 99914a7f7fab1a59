"""``sim.*`` functions on the simulation and its scripts: time and state, starting and stopping,
parameters, messages (key presses of ``--keys``), the status bar, thread timing, waiting
(``sim.wait``, ``sim.waitForSignal``: generators, see ``sims.simapi.table``), script
attributes and script functions."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from .context import Caller, SimError
from .values import flag, integer, number, numbers, text

PROGRAM_VERSION = 40600  # sim.getInt32Param(sim.intparam_program_version) for 4.x scenes
#: parameter ids (sim.intparam_* / floatparam_* / boolparam_* / stringparam_*)
INT_ERROR_REPORT, INT_VERSION, INT_CURRENT_PAGE, INT_IDLE_FPS = 0, 1, 5, 26
INT_ENGINE, INT_STEP_DIVIDER, INT_SPEED, INT_FLYCAM = 8, 9, 20, 28
FLOAT_TIME_STEP, FLOAT_DYN_STEP = 1, 2
BOOL_REALTIME, BOOL_HEADLESS, BOOL_DISPLAY, BOOL_DYNAMICS = 25, 26, 30, 16
STR_SCENE_PATH_AND_NAME, STR_SCENE_PATH, STR_SCENE_NAME, STR_SCENE_DIR = 13, 14, 15, 132


# -- simulation ----------------------------------------------------------------------------------
def get_simulation_time(c: Caller) -> float:
    return c.time


def get_simulation_time_step(c: Caller) -> float:
    return c.pass_dt


def get_simulation_state(c: Caller) -> int:
    return c.state_code()


def get_real_time_simulation(c: Caller) -> int:
    return 0


def is_real_time_simulation(c: Caller) -> int:
    return int(bool(c.store.params.get(("bool", BOOL_REALTIME), False)))


def get_system_time(c: Caller) -> float:
    return c.system_time()


def get_system_time_in_ms(c: Caller, previous: Any = -1) -> int:
    now = int(c.system_time() * 1000)
    prev = integer(previous, 1, -1)
    return now if prev < 0 else now - prev


def start_simulation(c: Caller) -> int:
    return c.start_simulation()


def stop_simulation(c: Caller, wait: Any = False) -> int:
    return c.stop_simulation()


def pause_simulation(c: Caller) -> int:
    return c.pause_simulation()


# -- parameters ----------------------------------------------------------------------------------
def _int_params(c: Caller) -> dict[int, int]:
    dt = float(getattr(c.world, "timestep", 0.005) or 0.005)
    return {
        INT_ERROR_REPORT: 1,
        INT_VERSION: PROGRAM_VERSION if c.new_api else 30600,
        INT_CURRENT_PAGE: 0,
        INT_IDLE_FPS: 8,
        INT_ENGINE: 0,  # sim.physics_bullet
        INT_STEP_DIVIDER: max(1, round(c.pass_dt / dt)),
        INT_SPEED: 0,
        INT_FLYCAM: -1,
        27: 1,  # scene unique id
    }


def get_int32_param(c: Caller, pid: Any) -> int:
    key = integer(pid, 1)
    got = c.store.params.get(("int", key))
    return int(got) if got is not None else _int_params(c).get(key, 0)


def set_int32_param(c: Caller, pid: Any, value: Any) -> int:
    c.store.params[("int", integer(pid, 1))] = integer(value, 2)
    return c.done


def get_float_param(c: Caller, pid: Any) -> float:
    key = integer(pid, 1)
    got = c.store.params.get(("float", key))
    if got is not None:
        return float(got)
    dt = float(getattr(c.world, "timestep", 0.005) or 0.005)
    return {FLOAT_TIME_STEP: c.pass_dt, FLOAT_DYN_STEP: dt}.get(key, 0.0)


def set_float_param(c: Caller, pid: Any, value: Any) -> int:
    c.store.params[("float", integer(pid, 1))] = number(value, 2)
    return c.done


def get_bool_param(c: Caller, pid: Any) -> bool:
    key = integer(pid, 1)
    got = c.store.params.get(("bool", key))
    if got is not None:
        return bool(got)
    return {BOOL_HEADLESS: True, BOOL_DISPLAY: False, BOOL_DYNAMICS: True}.get(key, False)


def set_bool_param(c: Caller, pid: Any, value: Any) -> int:
    c.store.params[("bool", integer(pid, 1))] = flag(value)
    return c.done


def get_string_param(c: Caller, pid: Any) -> str:
    """String parameters: the scene's path and name, and as CoppeliaSim's own scenes folder
    (``stringparam_scenedefaultdir``) the package's bundled scenes, where the scenes matching
    CoppeliaSim's ZeroMQ examples live (``messaging/...``)."""
    from pathlib import Path

    from sims.scene.resolve import BUNDLED_SCENES

    key = integer(pid, 1)
    got = c.store.params.get(("string", key))
    if got is not None:
        return str(got)
    source = Path(str(getattr(getattr(c.world, "source", None), "source", "") or "scene"))
    values = {
        STR_SCENE_PATH_AND_NAME: str(source),
        STR_SCENE_NAME: source.name,
        STR_SCENE_PATH: str(source.parent),
        STR_SCENE_DIR: str(BUNDLED_SCENES),
    }
    if key not in values:
        raise SimError(f"parameter {key} is not emulated")
    return values[key]


def set_string_param(c: Caller, pid: Any, value: Any) -> int:
    c.store.params[("string", integer(pid, 1))] = text(value, 2)
    return c.done


def get_array_param(c: Caller, pid: Any) -> list[float]:
    """sim.arrayparam_gravity (0): the scene's gravity, as its file or a script set it."""
    if integer(pid, 1) != 0:
        raise SimError(f"parameter {pid} is not emulated")
    return [float(v) for v in c.world.gravity]


def set_array_param(c: Caller, pid: Any, values: Any) -> int:
    """sim.setArrayParam(sim.arrayparam_gravity, {x, y, z}): gravity from the next step."""
    if integer(pid, 1) != 0:
        raise SimError(f"parameter {pid} is not emulated")
    xyz = numbers(values)
    if len(xyz) < 3:
        raise SimError("argument 2: three values (x, y, z) expected")
    c.world.set_gravity((xyz[0], xyz[1], xyz[2]))
    return c.done


# -- messages and the status bar -----------------------------------------------------------------
def get_simulator_message(c: Caller) -> tuple:
    """(message, auxiliary data, auxiliary data 2): -1 when no message waits; a key press of
    the run's ``--keys`` is ``sim.message_keypress`` (aux: key code, modifiers), delivered once
    when its time has come."""
    store = c.store
    now = c.time
    if not store.messages:
        sent = store.params.setdefault(("keys", "sent"), set())
        for i, (start, code) in enumerate(c.key_presses()):
            if i not in sent and start <= now + 1e-9:
                sent.add(i)
                store.messages.append((5, [code, 0, 0, 0]))
    if not store.messages:
        return -1, None, None
    message, aux = store.messages.pop(0)
    return message, aux, None


def add_statusbar_message(c: Caller, message: Any = None) -> int:
    c.status(text(message) if message is not None else "")
    return 1


def add_log(c: Caller, verbosity: Any, message: Any = None) -> None:
    c.status(text(message) if message is not None else "")


# -- auxiliary consoles: a headless run has no window, so their lines go where the status bar's go
def auxiliary_console_open(c: Caller, title: Any, *rest: Any) -> int:
    h = c.store.new_handle("console", 1)
    c.store.consoles[h] = [text(title), ""]
    return h


def auxiliary_console_print(c: Caller, h: Any, message: Any = None) -> int:
    """Text up to each newline becomes a line ``title: text``; ``nil`` clears (nothing kept)."""
    console = c.store.consoles.get(integer(h, 1))
    if console is None:
        return 0
    if message is None:
        console[1] = ""
        return 1
    *lines, console[1] = (console[1] + text(message)).split("\n")
    for line in lines:
        c.status(f"{console[0]}: {line}")
    return 1


def auxiliary_console_close(c: Caller, h: Any) -> int:
    console = c.store.consoles.pop(integer(h, 1), None)
    if console is not None and console[1]:
        c.status(f"{console[0]}: {console[1]}")
    return 0 if console is None else 1


def auxiliary_console_show(c: Caller, h: Any, show: Any = True) -> int:
    return 1 if integer(h, 1) in c.store.consoles else 0


# -- threads -------------------------------------------------------------------------------------
def set_thread_switch_timing(c: Caller, ms: Any) -> int:
    run = c.script
    if run is not None:
        run.switch_ms = integer(ms, 1)
    return c.done


def set_thread_automatic_switch(c: Caller, on: Any) -> Any:
    """Returns the previous setting (4.x); automatic switches happen while it is on."""
    run = c.script
    if run is None:
        return c.done
    before = run.auto_switch
    run.auto_switch = flag(on, True)
    return before if c.new_api else 1


def get_thread_automatic_switch(c: Caller) -> bool:
    run = c.script
    return True if run is None else bool(run.auto_switch)


def set_thread_switch_allowed(c: Caller, on: Any) -> Any:
    return set_thread_automatic_switch(c, on)


def wait(c: Caller, dt: Any, sim_time: Any = True) -> Iterator[None]:
    """Until ``dt`` simulated seconds passed (the run's clock when ``sim_time`` is false);
    returns the overshoot."""
    d = number(dt, 1)
    if not c.threaded:
        raise SimError("sim.wait can only be called from a threaded script or a client")
    if flag(sim_time, True):
        start = c.time
        while c.time - start < d - 1e-9:
            yield
        return c.time - start - d
    start = c.system_time()
    while c.system_time() - start < d - 1e-9:
        yield
    return 0.0


def wait_for_signal(c: Caller, name: Any) -> Iterator[None]:
    key = text(name)
    if not c.threaded:
        raise SimError("sim.waitForSignal can only be called from a threaded script or a client")
    while True:
        for kind in ("int", "float", "string"):
            if key in c.signals[kind]:
                return c.signals[kind][key]
        yield


def switch_thread(c: Caller) -> Iterator[None]:
    if c.threaded:
        yield


def step(c: Caller, wait_: Any = True) -> Iterator[None]:
    """A threaded script's sim.step (4.4+): the next simulation pass."""
    if c.threaded:
        yield


# -- scripts -------------------------------------------------------------------------------------
def set_script_attribute(c: Caller, h: Any, attribute: Any, value: Any) -> int:
    hh, attr = integer(h, 1), integer(attribute, 2)
    run = c.script if hh == -4 else (c.lua.script_by_handle(hh) if c.lua else None)
    if run is not None and attr == 0 and run.kind == "customization":
        run.active = flag(value)  # customizationscriptattribute_activeduringsimulation
    c.store.params[("script", hh, attr)] = value
    return c.done


def get_script_attribute(c: Caller, h: Any, attribute: Any) -> Any:
    return c.store.params.get(("script", integer(h, 1), integer(attribute, 2)))


def remove_script(c: Caller, h: Any) -> int:
    hh = integer(h, 1)
    run = c.script if hh == -4 else (c.lua.script_by_handle(hh) if c.lua else None)
    if run is None:
        raise SimError(f"script handle {hh} does not exist")
    run.removed = True
    return c.done


def get_script_handle(c: Caller, name: Any = None, *rest: Any) -> int:
    if name is None or (isinstance(name, int) and name == -4):
        return -1 if c.script is None else c.script.handle
    if c.lua is None:
        return -1
    if isinstance(name, int):  # 4.x sim.getScript(scriptType, objectHandle)
        run = c.lua.script_of_object(c.handle(rest[0]) if rest else -1)
    else:
        run = c.lua.script_named(text(name))
    return -1 if run is None else run.handle


def get_script(c: Caller, kind: Any, obj: Any = -1, name: Any = None) -> int:
    if integer(kind, 1) == -4:
        return -1 if c.script is None else c.script.handle
    if c.lua is None:
        raise SimError("the scene has no scripts running")
    o = integer(obj, 2, -1)
    if o == -1 and isinstance(name, (str, bytes)):
        o = c.world.find(text(name)) or -1
    run = c.lua.script_of_object(c.handle(o)) if o != -1 else None
    if run is None:
        raise SimError("script does not exist")
    return run.handle


def get_script_execution_count(c: Caller) -> int:
    return 0 if c.script is None else c.script.executions


def call_script_function(c: Caller, function: Any, script: Any, *args: Any) -> Any:
    """``sim.callScriptFunction('fn@objectName', scriptType, ...)`` (before 4.6) or
    ``(fn, scriptHandle, ...)``: calls a Lua function of a running script."""
    if c.lua is None:
        raise SimError("the scene has no scripts running")
    fname = text(function)
    fn, _, obj = fname.partition("@")
    if obj:
        run = c.lua.script_named(obj)
    else:
        run = c.lua.script_by_handle(integer(script, 2))
    if run is None or run.state is None:
        raise SimError(f"script for {fname!r} does not exist or is not running")
    try:
        out = c.lua.call_run(run, fn, args)
    except LookupError as exc:
        raise SimError(str(exc)) from None
    if not out:
        return None
    return out[0] if len(out) == 1 else tuple(out)


def get_script_simulation_parameter(c: Caller, h: Any, name: Any, as_buffer: Any = False) -> Any:
    """The parameter saved with the scene (or set since): a number when its text is one,
    else the text (``as_buffer``: always the text)."""
    obj = _script_object(c, h)
    value = c.store.script_params.get((obj, text(name, 2)))
    if isinstance(value, bytes) and not flag(as_buffer):
        try:
            number_ = float(value.decode("utf-8"))
        except (UnicodeDecodeError, ValueError):
            return value
        return int(number_) if number_.is_integer() and b"." not in value else number_
    return value


def set_script_simulation_parameter(c: Caller, h: Any, name: Any, value: Any) -> int:
    obj = _script_object(c, h)
    c.store.script_params[(obj, text(name, 2))] = value
    return c.done


def _script_object(c: Caller, h: Any) -> int:
    hh = integer(h, 1)
    if hh in (-4, -10):  # handle_self, handle_main_script
        return -1 if c.object is None else c.object
    run = c.lua.script_by_handle(hh) if c.lua is not None else None
    return run.object if run is not None else hh


def get_object_name_suffix(c: Caller) -> int:
    s = getattr(c, "suffix", None)
    return -1 if s is None else s


def set_stepping(c: Caller, enable: Any = True) -> int:
    """Stepping mode: the simulation advances on sim.step (a ZeroMQ client); a threaded script
    switches only where it asks to. Returns the caller's previous stepping level."""
    return c.set_stepping(flag(enable, True))


def get_stepping(c: Caller) -> bool:
    return c.get_stepping()


def remote_api_start(c: Caller, port: Any, *rest: Any) -> int:
    """simRemoteApi.start / simExtRemoteApiStart: the legacy server a child script starts (a
    temporary server; no socket is opened: see docs/lua.md)."""
    if c.lua is not None:
        c.lua.serve(integer(port, 1))
    return 0
