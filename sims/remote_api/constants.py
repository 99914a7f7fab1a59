"""Constants of CoppeliaSim's legacy remote API (``sim.py`` / ``simConst.py``, 4.2 era).

Names and values follow the CoppeliaSim manual (remoteApiConstants). Only constants that a
legacy script plausibly reads are listed; everything here is a plain ``int``.
"""

from __future__ import annotations

# --- return codes (bit flags, may be combined) -------------------------------------------------
simx_return_ok = 0x000000
simx_return_novalue_flag = 0x000001
simx_return_timeout_flag = 0x000002
simx_return_illegal_opmode_flag = 0x000004
simx_return_remote_error_flag = 0x000008
simx_return_split_progress_flag = 0x000010
simx_return_local_error_flag = 0x000020
simx_return_initialize_error_flag = 0x000040

# --- operation modes ---------------------------------------------------------------------------
simx_opmode_oneshot = 0x000000
simx_opmode_blocking = 0x010000
simx_opmode_oneshot_wait = 0x010000  # V-REP name of blocking
simx_opmode_continuous = 0x020000  # V-REP name of streaming
simx_opmode_streaming = 0x020000  # + delay in ms (0..65535)
simx_opmode_oneshot_split = 0x030000
simx_opmode_continuous_split = 0x040000
simx_opmode_streaming_split = 0x040000
simx_opmode_discontinue = 0x050000
simx_opmode_buffer = 0x060000
simx_opmode_remove = 0x070000

# --- message header offsets (simxGetInMessageInfo / simxGetOutMessageInfo) ------------------------
simx_headeroffset_crc = 0
simx_headeroffset_version = 2
simx_headeroffset_message_id = 3
simx_headeroffset_client_time = 7
simx_headeroffset_server_time = 11
simx_headeroffset_scene_id = 15
simx_headeroffset_server_state = 17

# --- special handles ---------------------------------------------------------------------------
sim_handle_all = -2
sim_handle_all_except_explicit = -3
sim_handle_self = -4
sim_handle_main_script = -5
sim_handle_tree = -6
sim_handle_chain = -7
sim_handle_single = -8
sim_handle_default = -9
sim_handle_all_except_self = -10
sim_handle_parent = -11
sim_handle_scene = -12
sim_handle_app = -13

# --- object types ------------------------------------------------------------------------------
sim_object_shape_type = 0
sim_object_joint_type = 1
sim_object_graph_type = 2
sim_object_camera_type = 3
sim_object_dummy_type = 4
sim_object_proximitysensor_type = 5
sim_object_reserved1 = 6
sim_object_reserved2 = 7
sim_object_path_type = 8
sim_object_visionsensor_type = 9
sim_object_volume_type = 10
sim_object_mill_type = 11
sim_object_forcesensor_type = 12
sim_object_light_type = 13
sim_object_mirror_type = 14
sim_object_octree_type = 15
sim_object_pointcloud_type = 16
sim_appobj_object_type = 109

# --- simulation states (sim.getSimulationState) ------------------------------------------------
sim_simulation_stopped = 0x00
sim_simulation_paused = 0x08
sim_simulation_advancing = 0x10
sim_simulation_advancing_firstafterstop = sim_simulation_advancing | 0x00
sim_simulation_advancing_running = sim_simulation_advancing | 0x01
sim_simulation_advancing_lastbeforepause = sim_simulation_advancing | 0x03
sim_simulation_advancing_firstafterpause = sim_simulation_advancing | 0x04
sim_simulation_advancing_abouttostop = sim_simulation_advancing | 0x05
sim_simulation_advancing_lastbeforestop = sim_simulation_advancing | 0x06

# --- parameters (simxGet*Parameter) ------------------------------------------------------------
sim_boolparam_hierarchy_visible = 0
sim_boolparam_console_visible = 1
sim_boolparam_collision_handling_enabled = 2
sim_boolparam_distance_handling_enabled = 3
sim_boolparam_ik_handling_enabled = 4
sim_boolparam_dynamics_handling_enabled = 6
sim_boolparam_realtime_simulation = 25
sim_intparam_error_report_mode = 0
sim_intparam_program_version = 1
sim_intparam_dynamic_step_divider = 7
sim_intparam_dynamic_engine = 8
sim_intparam_server_port_start = 9
sim_intparam_idle_fps = 26
sim_intparam_speedmodifier = 36
sim_intparam_mouse_x = 22
sim_intparam_mouse_y = 23
sim_floatparam_rand = 0
sim_floatparam_simulation_time_step = 1
sim_floatparam_stereo_distance = 2
sim_floatparam_dynamic_step_size = 3
sim_floatparam_mouse_wheel_zoom_factor = 4
sim_stringparam_application_path = 0
sim_stringparam_video_filename = 1
sim_arrayparam_gravity = 0
sim_arrayparam_fog = 1
sim_arrayparam_background_color1 = 3
sim_arrayparam_background_color2 = 4
sim_arrayparam_ambient_light = 5

# --- joint modes and misc ----------------------------------------------------------------------
sim_jointmode_passive = 0
sim_jointmode_motion = 1  # V-REP 3.x (deprecated motion mode)
sim_jointmode_motion_deprecated = 1
sim_jointmode_ik = 2
sim_jointmode_ik_deprecated = 2
sim_jointmode_ikdependent = 3
sim_jointmode_reserved_previously_ikdependent = 3
sim_jointmode_dependent = 4
sim_jointmode_force = 5
sim_joint_revolute_subtype = 10
sim_joint_prismatic_subtype = 11
sim_joint_spherical_subtype = 12

sim_scripttype_mainscript = 0
sim_scripttype_childscript = 1
sim_scripttype_addonscript = 2
sim_scripttype_customizationscript = 6
sim_scripttype_sandboxscript = 8

sim_physics_bullet = 0
sim_physics_ode = 1
sim_physics_vortex = 2
sim_physics_newton = 3

sim_api_error_report = 1
sim_api_error_output = 2
sim_api_warning_output = 4

#: Every opmode base value the module knows (the low 16 bits of streaming carry a delay).
OPMODE_BASES = (
    simx_opmode_oneshot,
    simx_opmode_blocking,
    simx_opmode_streaming,
    simx_opmode_oneshot_split,
    simx_opmode_streaming_split,
    simx_opmode_discontinue,
    simx_opmode_buffer,
    simx_opmode_remove,
)

#: The largest number of simultaneous connections the client library allows.
MAX_CONNECTIONS = 255

__all__ = [name for name in dict(globals()) if name.startswith(("simx_", "sim_"))]
