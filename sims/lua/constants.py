"""The constants a scene script reads, as ``sim.name`` (4.x) and ``sim_name`` (V-REP 3.x).

The legacy remote API's table (``sims.remote_api.constants``) supplies most values; this adds
the script-side ones: call types of child/customization scripts (V-REP 3.x: initialization 0,
cleanup 1, actuation 2, sensing 3; CoppeliaSim 4.x ``sim.syscb_*``), script attributes, object
special properties, dialog styles and parameters the course scenes read.
"""

from __future__ import annotations

from functools import lru_cache

from sims.remote_api import constants as _remote
from sims.simapi.constants import ADDED

#: V-REP 3.x ``sim_call_type`` values (an old-style script compares against these).
CHILD_CALLS = {"initialization": 0, "cleanup": 1, "actuation": 2, "sensing": 3, "threaded": 4}
CUSTOMIZATION_CALLS = {
    "initialization": 0,
    "cleanup": 1,
    "nonsimulation": 2,
    "lastbeforesimulation": 3,
    "firstaftersimulation": 4,
    "simulationactuation": 5,
    "simulationsensing": 6,
    "simulationpause": 7,
}
#: CoppeliaSim 4.x callback numbers (``sim.syscb_*``); an old-style 4.x script gets these.
SYSCB = {
    "init": 0,
    "cleanup": 1,
    "nonsimulation": 2,
    "beforesimulation": 3,
    "aftersimulation": 4,
    "actuation": 5,
    "sensing": 6,
    "suspend": 7,
    "suspended": 8,
    "resume": 9,
}

EXTRA = {
    "scripttype_mainscript": 0,
    "scripttype_childscript": 1,
    "scripttype_addonscript": 2,
    "scripttype_customizationscript": 6,
    "scripttype_threaded": 0x00F0,
    "childscriptattribute_automaticcascadingcalls": 3,
    "customizationscriptattribute_activeduringsimulation": 0,
    "customizationscriptattribute_cleanupbeforesave": 5,
    "childscriptattribute_enabled": 4,
    "scriptattribute_executioncount": 5,
    "scriptattribute_executiononce": 6,
    "scriptattribute_enabled": 4,
    "scriptattribute_debuglevel": 6,
    "objectspecialproperty_collidable": 0x0001,
    "objectspecialproperty_measurable": 0x0002,
    "objectspecialproperty_detectable_ultrasonic": 0x0010,
    "objectspecialproperty_detectable_infrared": 0x0020,
    "objectspecialproperty_detectable_laser": 0x0040,
    "objectspecialproperty_detectable_inductive": 0x0080,
    "objectspecialproperty_detectable_capacitive": 0x0100,
    "objectspecialproperty_renderable": 0x0200,
    "objectspecialproperty_detectable_all": 0x01F0,
    "objectspecialproperty_cuttable": 0x0400,
    "objectspecialproperty_pathplanning_ignored": 0x0800,
    "dlgstyle_message": 0,
    "dlgstyle_input": 1,
    "dlgstyle_ok": 2,
    "dlgstyle_ok_cancel": 3,
    "dlgstyle_yes_no": 4,
    "dlgstyle_dont_center": 32,
    "dlgret_still_open": 0,
    "dlgret_ok": 1,
    "dlgret_cancel": 2,
    "dlgret_yes": 3,
    "dlgret_no": 4,
    "intparam_error_report_mode": 0,
    "intparam_program_version": 1,
    "intparam_flymode_camera_handle": 28,
    "intparam_scene_unique_id": 27,
    "intparam_current_page": 5,
    "floatparam_simulation_time_step": 1,
    "boolparam_realtime_simulation": 25,
    "api_error_output": 1,
    "api_warning_output": 2,
    "handleflag_reljointbaseframe": 0x00200000,
    "handleflag_axis": 0x00800000,
    "buttonproperty_button": 0,
    "buttonproperty_label": 1,
    "buttonproperty_slider": 2,
    "buttonproperty_editbox": 3,
    "buttonproperty_staydown": 8,
    "buttonproperty_enabled": 16,
    "buttonproperty_isdown": 64,
    "buttonproperty_horizontallycentered": 256,
    "buttonproperty_ignoremouse": 512,
    "buttonproperty_borderless": 4096,
    "buttonproperty_verticallycentered": 8192,
    "buttonproperty_transparent": 2048,
    "buttonproperty_nobackgroundcolor": 1024,
    "buttonproperty_downupevent": 16384,
    "buttonproperty_closeaction": 32768,
    "ui_property_visible": 0x0001,
    "ui_property_visibleduringsimulationonly": 0x0002,
    "ui_property_moveable": 0x0004,
    "ui_property_relativetoleftborder": 0x0008,
    "ui_property_relativetotopborder": 0x0010,
    "ui_property_fixedwidthfont": 0x0020,
    "ui_property_systemblock": 0x0040,
    "ui_property_settocenter": 0x0080,
    "ui_property_rolledup": 0x0100,
    "ui_property_selectassociatedobject": 0x0200,
    "ui_property_visiblewhenobjectselected": 0x0400,
    "ui_property_systemblockcanmovetofront": 0x0800,
    "ui_property_pauseactive": 0x1000,
    "modelproperty_not_collidable": 0x0001,
    "modelproperty_not_visible": 0x0200,
    "object_dummy_type": 4,
    "object_octree_type": 15,
    "drawing_points": 0,
    "drawing_lines": 1,
    "drawing_triangles": 2,
    "drawing_cyclic": 0x0800,
    "light_omnidirectional_subtype": 1,
    "banner_fullyfacingcamera": 0x0200,
}


@lru_cache(maxsize=2)
def constants(new_style: bool) -> dict[str, int]:
    """Every constant by its 4.x name without the ``sim.`` prefix (``handle_self`` -> -4).
    Shared (cached): do not modify the returned dict."""
    out: dict[str, int] = {}
    for name in dir(_remote):
        if name.startswith("sim_"):
            out[name[4:]] = getattr(_remote, name)
    out.update(EXTRA)
    for name, value in ADDED.items():  # the one table's constants (sims/simapi/constants.py)
        out.setdefault(name, value)
    for k, v in SYSCB.items():
        out["syscb_" + k] = v
    if new_style:  # CoppeliaSim 4.x maps the old call types onto its callbacks
        child = {
            "initialization": 0,
            "cleanup": 1,
            "actuation": SYSCB["actuation"],
            "sensing": SYSCB["sensing"],
            "threaded": 10,
        }
        custom = {
            "initialization": 0,
            "cleanup": 1,
            "nonsimulation": 2,
            "lastbeforesimulation": 3,
            "firstaftersimulation": 4,
            "simulationactuation": SYSCB["actuation"],
            "simulationsensing": SYSCB["sensing"],
            "simulationpause": 11,
        }
    else:
        child, custom = CHILD_CALLS, CUSTOMIZATION_CALLS
    for k, v in child.items():
        out["childscriptcall_" + k] = v
    for k, v in custom.items():
        out["customizationscriptcall_" + k] = v
    return out
