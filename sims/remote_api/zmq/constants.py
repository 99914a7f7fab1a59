"""The ``sim.*`` constants a ZeroMQ remote API client sees (``sim.handle_world``, ...).

The ZeroMQ API names CoppeliaSim's constants without the legacy ``sim_`` prefix and with the same
values, so the legacy table (``..constants``) is reused, prefix dropped, and the names the legacy
API never had are added here (values from CoppeliaSim 4.x's ``sim`` module).
"""

from __future__ import annotations

from sims.simapi.constants import ADDED as _added

from .. import constants as _legacy

CONSTANTS: dict[str, int | float | str] = {
    name[len("sim_") :]: value
    for name, value in vars(_legacy).items()
    if name.startswith("sim_") and isinstance(value, (int, float, str))
}

CONSTANTS.update(
    {
        "handle_world": -1,
        # 4.6+ names of the object types
        "sceneobject_shape": 0,
        "sceneobject_joint": 1,
        "sceneobject_graph": 2,
        "sceneobject_camera": 3,
        "sceneobject_dummy": 4,
        "sceneobject_proximitysensor": 5,
        "sceneobject_path": 8,
        "sceneobject_visionsensor": 9,
        "sceneobject_forcesensor": 12,
        "sceneobject_light": 13,
        "sceneobject_octree": 15,
        "sceneobject_pointcloud": 16,
        "sceneobject_script": 17,
        # sim.addLog verbosities
        "verbosity_none": 0x000,
        "verbosity_errors": 0x100,
        "verbosity_warnings": 0x200,
        "verbosity_loadinfos": 0x300,
        "verbosity_scripterrors": 0x400,
        "verbosity_scriptwarnings": 0x500,
        "verbosity_scriptinfos": 0x600,
        "verbosity_infos": 0x700,
        "verbosity_debug": 0x800,
        "verbosity_trace": 0x900,
        "verbosity_tracelua": 0xA00,
        "verbosity_traceall": 0xB00,
        "verbosity_default": 0x300,
        "verbosity_undecorated": 0xF000,
        # joint types and modes (4.x names)
        "joint_revolute": 10,
        "joint_prismatic": 11,
        "joint_spherical": 12,
        "jointmode_kinematic": 0,
        "jointdynctrl_free": 0,
        "jointdynctrl_force": 1,
        "jointdynctrl_velocity": 2,
        "jointdynctrl_position": 3,
        "jointdynctrl_spring": 4,
        "jointdynctrl_callback": 5,
        # proximity sensor volumes
        "proximitysensor_pyramid": 0,
        "proximitysensor_cylinder": 1,
        "proximitysensor_disc": 2,
        "proximitysensor_cone": 3,
        "proximitysensor_ray": 4,
        # misc parameters scripts read
        "floatparam_simulation_time_step": _legacy.sim_floatparam_simulation_time_step,
        "intparam_idle_fps": _legacy.sim_intparam_idle_fps,
        "stringparam_scene_path_and_name": 13,
        "stringparam_scene_path": 14,
        "stringparam_scene_name": 15,
        "intparam_simulation_warning_disabled_mask": 22,
    }
)

for _name, _value in _added.items():  # the one table's constants (sims/simapi/constants.py)
    CONSTANTS.setdefault(_name, _value)

#: Values of getSimulationState.
SIMULATION_STOPPED = CONSTANTS["simulation_stopped"]
SIMULATION_PAUSED = CONSTANTS["simulation_paused"]
SIMULATION_RUNNING = CONSTANTS["simulation_advancing_running"]
HANDLE_WORLD = -1
HANDLE_ALL = CONSTANTS["handle_all"]
HANDLE_PARENT = CONSTANTS["handle_parent"]
HANDLE_SCENE = CONSTANTS["handle_scene"]

#: Object type numbers by the tree entries' ``kind``.
KIND_TYPES = {
    "shape": 0,
    "joint": 1,
    "graph": 2,
    "camera": 3,
    "dummy": 4,
    "proximity_sensor": 5,
    "path": 8,
    "vision_sensor": 9,
    "force_sensor": 12,
    "light": 13,
    "mirror": 14,
    "octree": 15,
    "point_cloud": 16,
}
