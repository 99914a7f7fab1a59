"""``sim.*`` functions on the simulation and the scripts: time, state, parameters, status bar,
thread timing, script attributes, dialogs, the remote API server."""

from __future__ import annotations

from typing import Any

from .api_core import Context, api
from .runtime import text, to_py


# -- simulation --------------------------------------------------------------------------------
@api("getSimulationTime")
def get_simulation_time(c: Context) -> Any:
    return c.host.time


@api("getSimulationTimeStep")
def get_simulation_time_step(c: Context) -> Any:
    return c.host.pass_dt


@api("getSimulationState")
def get_simulation_state(c: Context) -> Any:
    return c.host.state_code()


@api("getRealTimeSimulation")
def get_real_time_simulation(c: Context) -> Any:
    return 0  # the run's clock is virtual


@api("getSystemTimeInMs")
def get_system_time_in_ms(c: Context, previous: Any = -1) -> Any:
    now = int(c.host.time * 1000)
    return now if int(previous) < 0 else now - int(previous)


@api("getInt32Parameter")
def get_int32_parameter(c: Context, pid: Any) -> Any:
    return c.host.int_params.get(int(pid), 0)


@api("setInt32Parameter")
def set_int32_parameter(c: Context, pid: Any, value: Any) -> Any:
    c.host.int_params[int(pid)] = int(value)
    return 1


@api("getFloatParameter")
def get_float_parameter(c: Context, pid: Any) -> Any:
    return c.host.pass_dt if int(pid) == 1 else 0.0


@api("getBoolParameter")
def get_bool_parameter(c: Context, pid: Any) -> Any:
    return False


@api("addStatusbarMessage")
def add_statusbar_message(c: Context, message: Any = None) -> Any:
    c.host.status(text(message) if message is not None else "")
    return 1


@api("addLog")
def add_log(c: Context, verbosity: Any, message: Any) -> Any:
    return add_statusbar_message(c, message)


@api("setThreadSwitchTiming")
def set_thread_switch_timing(c: Context, ms: Any) -> Any:
    c.script.switch_ms = int(ms)
    return 1


@api("setThreadAutomaticSwitch")
def set_thread_automatic_switch(c: Context, on: Any) -> Any:
    c.script.auto_switch = bool(on)
    return 1


@api("setScriptAttribute")
def set_script_attribute(c: Context, h: Any, attribute: Any, value: Any) -> Any:
    if int(h) == -4 and int(attribute) == 0 and c.script.kind == "customization":
        c.script.active = bool(value)  # customizationscriptattribute_activeduringsimulation
    c.host.script_attributes[(int(h), int(attribute))] = to_py(value)
    return 1


@api("getScriptAttribute")
def get_script_attribute(c: Context, h: Any, attribute: Any) -> Any:
    return c.host.script_attributes.get((int(h), int(attribute)))


@api("removeScript")
def remove_script(c: Context, h: Any) -> Any:
    target = c.script if int(h) == -4 else c.host.script_by_handle(int(h))
    if target is None:
        return c.state.fail(f"script handle {int(h)} does not exist")
    target.removed = True
    return 1


@api("getScriptHandle")
def get_script_handle(c: Context, name: Any = None) -> Any:
    if name is None:
        return c.script.handle
    s = c.host.script_named(text(name))
    return -1 if s is None else s.handle


@api("getScriptExecutionCount")
def get_script_execution_count(c: Context) -> Any:
    return c.script.executions


@api("displayDialog")
def display_dialog(c: Context, title: Any, main: Any, style: Any, modal: Any, *rest: Any) -> Any:
    c.host.status(f"dialog: {text(title)}: {text(main)}")
    return c.host.new_ui({"dialog": text(main)})


@api("endDialog")
def end_dialog(c: Context, h: Any) -> Any:
    c.host.uis.pop(int(h), None)
    return 1


@api("getDialogResult")
def get_dialog_result(c: Context, h: Any) -> Any:
    return 1  # a headless dialog is answered "ok" at once


@api("auxFunc")
def aux_func(c: Context, what: Any, *args: Any) -> Any:
    return None  # the helper functions behind it open windows; nothing to do headless


@api("remoteApiStart")
def remote_api_start(c: Context, port: Any, *rest: Any) -> Any:
    c.host.serve(int(port))
    return 0
