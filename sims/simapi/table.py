"""The one table of ``sim.*`` functions, for the scene scripts (Lua) and ZeroMQ clients alike.

Declared here, in one place (issue 34: no registration by the side effect of an import): name
-> implementation ``fn(caller, *plain_args)``. A generator function is a *blocking* function:
each ``yield`` waits for the next simulation pass (the Lua binding yields the script's
coroutine; the ZeroMQ server steps the simulation for its client), and its return value is the
result. ``sims.lua.binding`` converts Lua values at one edge, ``sims.remote_api.zmq.functions``
CBOR-shaped values at the other. Names are CoppeliaSim 4.x's; V-REP 3.x scripts reach the same
entries through ``OLD_NAMES`` (``simGetObjectHandle`` -> ``sim.getObjectHandle``) and the
renamed functions listed in ``ALIASES``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from . import data, joints, mechanisms, motion, objects, poses, sensors, simulation, ui

Fn = Callable[..., Any]

FUNCTIONS: dict[str, Fn] = {
    # objects: handles, names, the tree
    "sim.getObject": objects.get_object,
    "sim.getObjectHandle": objects.get_object_handle,
    "sim.isHandle": objects.is_handle,
    "sim.getObjectAlias": objects.get_object_alias,
    "sim.setObjectAlias": objects.set_object_alias,
    "sim.getObjectName": objects.get_object_name,
    "sim.setObjectName": objects.set_object_name,
    "sim.getObjectType": objects.get_object_type,
    "sim.getObjectParent": objects.get_object_parent,
    "sim.getObjectChild": objects.get_object_child,
    "sim.getObjectsInTree": objects.get_objects_in_tree,
    "sim.getObjects": objects.get_objects,
    "sim.getObjectAssociatedWithScript": objects.get_object_associated_with_script,
    "sim.getObjectSelection": objects.get_object_selection,
    "sim.getObjectSel": objects.get_object_selection,
    "sim.setObjectSelection": objects.set_object_selection,
    "sim.setObjectSel": objects.set_object_selection,
    "sim.addObjectToSelection": objects.add_object_to_selection,
    "sim.removeObjectFromSelection": objects.remove_object_from_selection,
    "sim.getObjectSizeFactor": objects.get_object_size_factor,
    "sim.getObjectSpecialProperty": objects.get_special,
    "sim.setObjectSpecialProperty": objects.set_special,
    "sim.getModelProperty": objects.get_model_property,
    "sim.setModelProperty": objects.set_model_property,
    "sim.getNameSuffix": objects.get_name_suffix,
    "sim.setNameSuffix": objects.set_name_suffix,
    # creating, removing, parenting, copying
    "sim.createDummy": objects.create_dummy,
    "sim.createPrimitiveShape": objects.create_primitive_shape,
    "sim.createPureShape": objects.create_pure_shape,
    "sim.removeObject": objects._remove_object,
    "sim.removeObjects": objects.remove_objects,
    "sim.removeModel": objects.remove_model,
    "sim.setObjectParent": objects.set_object_parent,
    "sim.copyPasteObjects": objects.copy_paste_objects,
    "sim.scaleObject": objects.scale_object,
    "sim.scaleObjects": objects.scale_objects,
    "sim.resetDynamicObject": objects.reset_dynamic_object,
    "sim.getConfigurationTree": objects.get_configuration_tree,
    "sim.setConfigurationTree": objects.set_configuration_tree,
    "sim.loadModel": objects.load_model,
    "sim.loadScene": objects.load_scene,
    "sim.createCollection": objects.create_collection,
    "sim.addItemToCollection": objects.add_item_to_collection,
    "sim.getCollectionObjects": objects.get_collection_objects,
    "sim.getCollectionHandle": objects.get_collection_handle,
    # frames
    "sim.getObjectPosition": poses.get_object_position,
    "sim.getObjectOrientation": poses.get_object_orientation,
    "sim.getObjectQuaternion": poses.get_object_quaternion,
    "sim.getObjectPose": poses.get_object_pose,
    "sim.getObjectMatrix": poses.get_object_matrix,
    "sim.setObjectPosition": poses.set_object_position,
    "sim.setObjectOrientation": poses.set_object_orientation,
    "sim.setObjectQuaternion": poses.set_object_quaternion,
    "sim.setObjectPose": poses.set_object_pose,
    "sim.setObjectMatrix": poses.set_object_matrix,
    "sim.getObjectVelocity": poses.get_object_velocity,
    "sim.getVelocity": poses.get_velocity,
    # matrices
    "sim.buildIdentityMatrix": poses.build_identity_matrix,
    "sim.buildMatrix": poses.build_matrix,
    "sim.buildMatrixQ": poses.build_matrix_q,
    "sim.buildPose": poses.build_pose,
    "sim.multiplyMatrices": poses.multiply_matrices,
    "sim.multiplyPoses": poses.multiply_poses,
    "sim.getMatrixInverse": poses.get_matrix_inverse,
    "sim.invertMatrix": poses.invert_matrix,
    "sim.getPoseInverse": poses.get_pose_inverse,
    "sim.multiplyVector": poses.multiply_vector,
    "sim.getEulerAnglesFromMatrix": poses.get_euler_angles_from_matrix,
    "sim.getQuaternionFromMatrix": poses.get_quaternion_from_matrix,
    "sim.getRotationAxis": poses.get_rotation_axis,
    "sim.rotateAroundAxis": poses.rotate_around_axis,
    "sim.interpolateMatrices": poses.interpolate_matrices,
    "sim.interpolatePoses": poses.interpolate_poses,
    "sim.poseToMatrix": poses.pose_to_matrix,
    "sim.matrixToPose": poses.matrix_to_pose,
    # joints and forces
    "sim.getJointPosition": joints.get_joint_position,
    "sim.setJointPosition": joints.set_joint_position,
    "sim.setJointTargetPosition": joints.set_joint_target_position,
    "sim.getJointTargetPosition": joints.get_joint_target_position,
    "sim.setJointTargetVelocity": joints.set_joint_target_velocity,
    "sim.getJointTargetVelocity": joints.get_joint_target_velocity,
    "sim.getJointVelocity": joints.get_joint_velocity,
    "sim.getJointForce": joints.get_joint_force,
    "sim.setJointForce": joints.set_joint_force,
    "sim.setJointMaxForce": joints.set_joint_force,
    "sim.getJointMaxForce": joints.get_joint_max_force,
    "sim.setJointTargetForce": joints.set_joint_target_force,
    "sim.getJointTargetForce": joints.get_joint_max_force,
    "sim.getJointType": joints.get_joint_type,
    "sim.getJointInterval": joints.get_joint_interval,
    "sim.getJointMode": joints.get_joint_mode,
    "sim.setJointMode": joints.set_joint_mode,
    "sim.isDynamicallyEnabled": joints.is_dynamically_enabled,
    "sim.addForce": joints.add_force,
    "sim.addForceAndTorque": joints.add_force_and_torque,
    "sim.readForceSensor": joints.read_force_sensor,
    "sim.breakForceSensor": joints.break_force_sensor,
    # sensors, collisions, distances
    "sim.readProximitySensor": sensors.read_proximity_sensor,
    "sim.handleProximitySensor": sensors.handle_proximity_sensor,
    "sim.resetProximitySensor": sensors.reset_proximity_sensor,
    "sim.checkProximitySensor": sensors.check_proximity_sensor,
    "sim.checkProximitySensorEx": sensors.check_proximity_sensor_ex,
    "sim.checkProximitySensorEx2": sensors.check_proximity_sensor_ex2,
    "sim.readVisionSensor": sensors.read_vision_sensor,
    "sim.handleVisionSensor": sensors.handle_vision_sensor,
    "sim.getVisionSensorImg": sensors.get_vision_sensor_img,
    "sim.getVisionSensorImage": sensors.get_vision_sensor_image,
    "sim.getVisionSensorCharImage": sensors.get_vision_sensor_char_image,
    "sim.getVisionSensorResolution": sensors.get_vision_sensor_resolution,
    "sim.setVisionSensorImg": sensors.set_vision_sensor_img,
    "sim.checkCollision": sensors.check_collision,
    "sim.checkDistance": sensors.check_distance,
    "sim.getCollisionHandle": sensors.get_collision_handle,
    "sim.getDistanceHandle": sensors.get_distance_handle,
    "sim.handleCollision": sensors.handle_collision,
    "sim.readCollision": sensors.read_collision,
    "sim.handleDistance": sensors.handle_distance,
    "sim.readDistance": sensors.read_distance,
    # simulation, parameters, messages
    "sim.getSimulationTime": simulation.get_simulation_time,
    "sim.getSimulationTimeStep": simulation.get_simulation_time_step,
    "sim.getSimulationState": simulation.get_simulation_state,
    "sim.getRealTimeSimulation": simulation.get_real_time_simulation,
    "sim.isRealTimeSimulation": simulation.is_real_time_simulation,
    "sim.getSystemTime": simulation.get_system_time,
    "sim.getSystemTimeInMs": simulation.get_system_time_in_ms,
    "sim.startSimulation": simulation.start_simulation,
    "sim.stopSimulation": simulation.stop_simulation,
    "sim.pauseSimulation": simulation.pause_simulation,
    "sim.getInt32Param": simulation.get_int32_param,
    "sim.setInt32Param": simulation.set_int32_param,
    "sim.getFloatParam": simulation.get_float_param,
    "sim.setFloatParam": simulation.set_float_param,
    "sim.getBoolParam": simulation.get_bool_param,
    "sim.setBoolParam": simulation.set_bool_param,
    "sim.getStringParam": simulation.get_string_param,
    "sim.setStringParam": simulation.set_string_param,
    "sim.getArrayParam": simulation.get_array_param,
    "sim.getSimulatorMessage": simulation.get_simulator_message,
    "sim.addStatusbarMessage": simulation.add_statusbar_message,
    "sim.addLog": simulation.add_log,
    # threads and waiting (generators: blocking)
    "sim.setThreadSwitchTiming": simulation.set_thread_switch_timing,
    "sim.setThreadAutomaticSwitch": simulation.set_thread_automatic_switch,
    "sim.getThreadAutomaticSwitch": simulation.get_thread_automatic_switch,
    "sim.setThreadSwitchAllowed": simulation.set_thread_switch_allowed,
    "sim.wait": simulation.wait,
    "sim.switchThread": simulation.switch_thread,
    "sim.step": simulation.step,
    "sim.setStepping": simulation.set_stepping,
    "sim.getStepping": simulation.get_stepping,
    "simRemoteApi.start": simulation.remote_api_start,
    "sim.waitForSignal": simulation.wait_for_signal,
    # scripts
    "sim.setScriptAttribute": simulation.set_script_attribute,
    "sim.getScriptAttribute": simulation.get_script_attribute,
    "sim.removeScript": simulation.remove_script,
    "sim.getScriptHandle": simulation.get_script_handle,
    "sim.getScript": simulation.get_script,
    "sim.getScriptExecutionCount": simulation.get_script_execution_count,
    "sim.callScriptFunction": simulation.call_script_function,
    "sim.getScriptSimulationParameter": simulation.get_script_simulation_parameter,
    "sim.setScriptSimulationParameter": simulation.set_script_simulation_parameter,
    # data: signals, custom data, packing, bits, object parameters
    **{"sim." + k: v for k, v in data.SIGNALS.items()},
    "sim.getSignalName": data.get_signal_name,
    "sim.writeCustomDataBlock": data.write_custom_data_block,
    "sim.readCustomDataBlock": data.read_custom_data_block,
    "sim.readCustomDataBlockTags": data.read_custom_data_block_tags,
    "sim.writeCustomTableData": data.write_custom_table_data,
    "sim.readCustomTableData": data.read_custom_table_data,
    **{"sim." + k: v for k, v in data.PACKING.items()},
    "sim.packTable": data.pack_table,
    "sim.unpackTable": data.unpack_table,
    "sim.transformBuffer": data.transform_buffer,
    **{"sim." + k: v for k, v in data.BITS.items()},
    "sim.tubeOpen": data.tube_open,
    "sim.tubeWrite": data.tube_write,
    "sim.tubeRead": data.tube_read,
    "sim.tubeStatus": data.tube_status,
    "sim.tubeClose": data.tube_close,
    "sim.setObjectFloatParam": data.set_object_float_param,
    "sim.getObjectFloatParam": data.get_object_float_param,
    "sim.setObjectInt32Param": data.set_object_int_param,
    "sim.getObjectInt32Param": data.get_object_int_param,
    "sim.setObjectStringParam": data.set_object_string_param,
    "sim.getObjectStringParam": data.get_object_string_param,
    "sim.setExplicitHandling": data.set_explicit_handling,
    "sim.getExplicitHandling": data.get_explicit_handling,
    # motion (Ruckig)
    "sim.rmlPos": motion.rml_pos,
    "sim.rmlVel": motion.rml_vel,
    "sim.rmlStep": motion.rml_step,
    "sim.rmlRemove": motion.rml_remove,
    "sim.ruckigPos": motion.rml_pos,
    "sim.ruckigVel": motion.rml_vel,
    "sim.ruckigStep": motion.rml_step,
    "sim.ruckigRemove": motion.rml_remove,
    "sim.moveToConfig": motion.move_to_config,
    "sim.moveToPose": motion.move_to_pose,
    "sim.rmlMoveToJointPositions": motion.rml_move_to_joint_positions,
    "sim.rmlMoveToPosition": motion.rml_move_to_position,
    # IK groups and paths (the World's kinematics and path objects)
    "sim.getIkGroupHandle": mechanisms.get_ik_group_handle,
    "sim.handleIkGroup": mechanisms.handle_ik_group,
    "sim.getConfigForTipPose": mechanisms.get_config_for_tip_pose,
    "sim.generateIkPath": mechanisms.generate_ik_path,
    "sim.getPathPosition": mechanisms.get_path_position,
    "sim.setPathPosition": mechanisms.set_path_position,
    "sim.getPathLength": mechanisms.get_path_length,
    "sim.setPathTargetNominalVelocity": mechanisms.set_path_target_nominal_velocity,
    "sim.getPositionOnPath": mechanisms.get_position_on_path,
    "sim.getOrientationOnPath": mechanisms.get_orientation_on_path,
    "sim.getClosestPositionOnPath": mechanisms.get_path_distance,
    "sim.followPath": mechanisms.follow_path,
    # user interfaces, dialogs, drawing objects
    "sim.getUIHandle": ui.get_ui_handle,
    "sim.getUIProperty": ui.get_ui_property,
    "sim.setUIProperty": ui.set_ui_property,
    "sim.getUIEventButton": ui.get_ui_event_button,
    "sim.getUISlider": ui.get_ui_slider,
    "sim.setUISlider": ui.set_ui_slider,
    "sim.setUIButtonLabel": ui.set_ui_button_label,
    "sim.getUIButtonLabel": ui.get_ui_button_label,
    "sim.getUIButtonProperty": ui.get_ui_button_property,
    "sim.setUIButtonProperty": ui.set_ui_button_property,
    "sim.removeUI": ui.remove_ui,
    **ui.SIMUI,
    "sim.displayDialog": ui.display_dialog,
    "sim.endDialog": ui.end_dialog,
    "sim.getDialogResult": ui.get_dialog_result,
    "sim.getDialogInput": ui.get_dialog_input,
    "sim.msgBox": ui.msg_box,
    "sim.auxFunc": ui.aux_func,
    "sim.addDrawingObject": ui.add_drawing_object,
    "sim.addDrawingObjectItem": ui.add_drawing_object_item,
    "sim.addDrawingObjectItems": ui.add_drawing_object_items,
    "sim.removeDrawingObject": ui.remove_drawing_object,
    "sim.addBanner": ui.add_banner,
    "sim.removeBanner": ui.remove_banner,
}

#: Functions renamed over the versions: the older name -> the table's name.
ALIASES = {
    "sim.getInt32Parameter": "sim.getInt32Param",
    "sim.setInt32Parameter": "sim.setInt32Param",
    "sim.getFloatParameter": "sim.getFloatParam",
    "sim.setFloatParameter": "sim.setFloatParam",
    "sim.getBoolParameter": "sim.getBoolParam",
    "sim.setBoolParameter": "sim.setBoolParam",
    "sim.getStringParameter": "sim.getStringParam",
    "sim.setStringParameter": "sim.setStringParam",
    "sim.getArrayParameter": "sim.getArrayParam",
    "sim.setObjectFloatParameter": "sim.setObjectFloatParam",
    "sim.getObjectFloatParameter": "sim.getObjectFloatParam",
    "sim.setObjectInt32Parameter": "sim.setObjectInt32Param",
    "sim.getObjectInt32Parameter": "sim.getObjectInt32Param",
    "sim.setObjectStringParameter": "sim.setObjectStringParam",
    "sim.getObjectStringParameter": "sim.getObjectStringParam",
    "sim.setIntegerSignal": "sim.setInt32Signal",
    "sim.getIntegerSignal": "sim.getInt32Signal",
    "sim.clearIntegerSignal": "sim.clearInt32Signal",
}
for _old, _new in ALIASES.items():
    FUNCTIONS.setdefault(_old, FUNCTIONS[_new])

#: V-REP 3.x global names that are not ``sim`` + the capitalised 4.x name.
OLD_NAMES = {
    "simExtRemoteApiStart": "simRemoteApi.start",
    "simGetIntegerParameter": "sim.getInt32Parameter",
    "simSetIntegerParameter": "sim.setInt32Parameter",
    "simGetFloatingParameter": "sim.getFloatParameter",
    "simSetFloatingParameter": "sim.setFloatParameter",
    "simRMLMoveToJointPositions": "sim.rmlMoveToJointPositions",
    "simRMLMoveToPosition": "sim.rmlMoveToPosition",
    "simRMLPos": "sim.rmlPos",
    "simRMLVel": "sim.rmlVel",
    "simRMLStep": "sim.rmlStep",
    "simRMLRemove": "sim.rmlRemove",
}

# V-REP 3.x's custom UI plug-in: simExtCustomUI_create... are simUI.create...
OLD_NAMES.update(
    {"simExtCustomUI_" + n.partition(".")[2]: n for n in FUNCTIONS if n.startswith("simUI.")}
)

#: Blocking functions (generators): computed from the table, not declared twice.
BLOCKING = frozenset(n for n, f in FUNCTIONS.items() if inspect.isgeneratorfunction(f))


def old_name(new: str) -> str:
    """``sim.getObjectHandle`` -> ``simGetObjectHandle`` (V-REP 3.x global)."""
    member = new.partition(".")[2]
    return "sim" + member[0].upper() + member[1:]


def lookup(name: str) -> Fn | None:
    """The implementation of a 4.x name (``sim.x`` or ``simUI.x``)."""
    return FUNCTIONS.get(name)
