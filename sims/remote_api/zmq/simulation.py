"""The ``sim.*`` simulation, stepping, time, parameter, signal and log functions.

Stepping follows CoppeliaSim's ZeroMQ add-on: ``sim.setStepping(True)`` raises the calling
client's stepping level and returns the previous level; while any client steps, the simulation
advances only on ``sim.step()`` (one 50 ms simulation pass each). Without stepping the
simulation runs free on the run's clock, and ``sim.step()`` waits for the next pass.
``sim.stopSimulation()`` sets every client's stepping level back to 0, as the add-on does, and
puts the scene back to its initial state. Signals are the same tables the legacy API's
``simxSet...Signal`` use, so legacy and ZeroMQ clients of one run see each other's signals.
"""

from __future__ import annotations

import ctypes
from typing import Any

from .. import constants as C
from ..server import RUNNING
from .constants import SIMULATION_RUNNING
from .registry import FUNCTIONS, api
from .server import ZmqServer

#: sim.getInt32Param(sim.intparam_program_version): the API generation emulated (4.6.0).
PROGRAM_VERSION = 40600


# --- simulation --------------------------------------------------------------------------------
@api("startSimulation")
def start_simulation(srv: ZmqServer) -> int:
    """1 when started (or resumed), 0 when it was already running."""
    sim = srv.simulator
    sim.load()
    if sim.state == RUNNING:
        return 0
    sim.start()
    return 1


@api("pauseSimulation")
def pause_simulation(srv: ZmqServer) -> int:
    sim = srv.simulator
    if sim.state != RUNNING:
        return 0
    sim.pause()
    return 1


@api("stopSimulation")
def stop_simulation(srv: ZmqServer, wait: Any = False) -> int:
    sim = srv.simulator
    for uuid in srv.stepping:
        srv.stepping[uuid] = 0
    srv.apply_stepping()
    if sim.state == "stopped":
        return 0
    sim.stop()
    srv.targets.clear()
    return 1


@api("getSimulationState")
def get_simulation_state(srv: ZmqServer) -> int:
    state = srv.simulator.state_code()
    return SIMULATION_RUNNING if state == 0x11 else state


@api("getSimulationTime")
def get_simulation_time(srv: ZmqServer) -> float:
    return float(srv.simulator.sim_time)


@api("getSimulationTimeStep")
def get_simulation_time_step(srv: ZmqServer) -> float:
    return float(srv.simulator.pass_dt)


@api("getSystemTime")
def get_system_time(srv: ZmqServer) -> float:
    """Seconds on the run's clock (virtual unless --realtime)."""
    return float(srv.session.clock.now())


@api("isRealTimeSimulation")
def is_real_time_simulation(srv: ZmqServer) -> int:
    return int(srv.session.clock.realtime)


# --- stepping ----------------------------------------------------------------------------------
@api("setStepping")
def set_stepping(srv: ZmqServer, enable: Any = True) -> int:
    """Returns the caller's previous stepping level."""
    uuid = srv.client_uuid
    previous = srv.stepping.get(uuid, 0)
    srv.stepping[uuid] = previous + 1 if enable else max(0, previous - 1)
    srv.apply_stepping()
    return previous


@api("getStepping")
def get_stepping(srv: ZmqServer) -> bool:
    return srv.stepping.get(srv.client_uuid, 0) > 0


@api("step")
def step(srv: ZmqServer, wait: Any = True) -> None:
    """One simulation pass in stepping mode (once every stepping client asked for it);
    without stepping, wait for the next pass. A stopped or paused simulation does not move.
    The rules are the server's (``ZmqServer.step``): they hold for every client."""
    srv.step()


# --- parameters --------------------------------------------------------------------------------
def _int_params(srv: ZmqServer) -> dict[int, Any]:
    sim = srv.simulator
    return {
        C.sim_intparam_program_version: PROGRAM_VERSION,
        C.sim_intparam_dynamic_engine: C.sim_physics_bullet,
        C.sim_intparam_dynamic_step_divider: sim.steps_per_pass,
        C.sim_intparam_idle_fps: 8,
        C.sim_intparam_speedmodifier: 0,
    }


def _float_params(srv: ZmqServer) -> dict[int, Any]:
    sim = srv.simulator
    return {
        C.sim_floatparam_simulation_time_step: sim.pass_dt,
        C.sim_floatparam_dynamic_step_size: sim.pass_dt / max(1, sim.steps_per_pass),
    }


def _bool_params(srv: ZmqServer) -> dict[int, Any]:
    return {
        C.sim_boolparam_realtime_simulation: srv.session.clock.realtime,
        C.sim_boolparam_dynamics_handling_enabled: True,
    }


def _param_getter(kind: str, table, cast) -> None:
    func = f"sim.get{kind}Param"

    def getter(srv: ZmqServer, param: Any) -> Any:
        pid = srv.handle_arg(param, func, 1)
        key = (kind, pid)
        if key in srv.params:
            return cast(srv.params[key])
        values = table(srv)
        if pid not in values:
            srv.fail("argument", f"parameter {pid} is not emulated", func)
        return cast(values[pid])

    FUNCTIONS[func] = getter


def _param_setter(kind: str, table, cast) -> None:
    func = f"sim.set{kind}Param"

    def setter(srv: ZmqServer, param: Any, value: Any) -> None:
        pid = srv.handle_arg(param, func, 1)
        if pid not in table(srv) and pid != C.sim_boolparam_realtime_simulation:
            srv.fail("argument", f"parameter {pid} is not emulated", func)
        srv.params[(kind, pid)] = cast(value)

    FUNCTIONS[func] = setter


for _kind, _table, _cast in (
    ("Int32", _int_params, int),
    ("Float", _float_params, float),
    ("Bool", _bool_params, bool),
):
    _param_getter(_kind, _table, _cast)
    _param_setter(_kind, _table, _cast)


@api("getArrayParam")
def get_array_param(srv: ZmqServer, param: Any) -> list[float]:
    if srv.handle_arg(param, "sim.getArrayParam", 1) != C.sim_arrayparam_gravity:
        srv.fail("argument", f"parameter {param} is not emulated", "sim.getArrayParam")
    return [0.0, 0.0, -9.81]


@api("getStringParam")
def get_string_param(srv: ZmqServer, param: Any) -> str:
    pid = srv.handle_arg(param, "sim.getStringParam", 1)
    if pid == 14:  # stringparam_scene_name
        return str(srv.simulator.scene)
    srv.fail("argument", f"parameter {pid} is not emulated", "sim.getStringParam")


# --- signals -----------------------------------------------------------------------------------
_CAST = {
    "int": lambda srv, v, f: ctypes.c_int32(srv.handle_arg(v, f, 2)).value,
    "float": lambda srv, v, f: srv.number_arg(v, f, 2),
    "string": lambda srv, v, f: v.encode("utf-8") if isinstance(v, str) else bytes(v),
}


def _signal_functions(kind: str, *names: str) -> None:
    table_of = lambda srv: srv.simulator.signals[kind]  # noqa: E731

    for name in names:

        def setter(srv: ZmqServer, signal: Any, value: Any, _name=name) -> None:
            func = f"sim.set{_name}Signal"
            key = srv.string_arg(signal, func, 1)
            if kind == "string" and not isinstance(value, (str, bytes, bytearray)):
                srv.fail("argument", "argument 2: string expected", func)
            table_of(srv)[key] = _CAST[kind](srv, value, func)

        def getter(srv: ZmqServer, signal: Any, _name=name) -> Any:
            """The value, or None when the signal is not set (as CoppeliaSim answers)."""
            value = table_of(srv).get(srv.string_arg(signal, f"sim.get{_name}Signal", 1))
            if kind == "string" and value is not None:
                try:
                    return bytes(value).decode("utf-8")
                except UnicodeDecodeError:
                    return bytes(value)
            return value

        def clearer(srv: ZmqServer, signal: Any = None, _name=name) -> None:
            if signal is None or signal == "":
                table_of(srv).clear()
            else:
                table_of(srv).pop(srv.string_arg(signal, f"sim.clear{_name}Signal", 1), None)

        FUNCTIONS[f"sim.set{name}Signal"] = setter
        FUNCTIONS[f"sim.get{name}Signal"] = getter
        FUNCTIONS[f"sim.clear{name}Signal"] = clearer


_signal_functions("int", "Int32", "Integer")
_signal_functions("float", "Float", "Double")
_signal_functions("string", "String")


# --- messages ----------------------------------------------------------------------------------
@api("addLog")
def add_log(srv: ZmqServer, verbosity: Any, message: Any = None) -> None:
    """Shown on stderr as CoppeliaSim shows it in its status bar; kept for the run's result."""
    text = srv.string_arg(message if message is not None else "", "sim.addLog", 2)
    srv.simulator.statusbar.append(text)
    srv.session.status(text)


@api("addStatusbarMessage")
def add_statusbar_message(srv: ZmqServer, message: Any) -> None:
    add_log(srv, 0, message)
