"""Behaviours an audit found unguarded: each of these could be broken without any other test
failing (a mutation of the code went unnoticed), and each is visible to a user.

- a velocity-mode revolute joint of an XML scene turns at its target speed in rad/s (the file
  stores degrees per second);
- a new max force reaches a motor that is already running at a target velocity.
"""

from __future__ import annotations

import math

import pytest

from sims.scene.load import load_scene
from sims.world import World

ARM_XML = """<?xml version="1.0" encoding="UTF-8"?>
<CoppeliaSim>
    <filetype>simpleScene</filetype>
    <xmlSerializationNb>1</xmlSerializationNb>
    <prgVer>40100</prgVer>
    <dynamics><gravity>0 0 -9.81</gravity></dynamics>
    <simulation><simulationTimeStep>0.05</simulationTimeStep></simulation>
    <shape>
        <common><name>base</name>
            <localFrame><position>0 0 0.5</position><euler>0 0 0</euler></localFrame></common>
        <primitive><type>cuboid</type><size>0.1 0.1 0.1</size></primitive>
        <dynamics><mass>5</mass><switches><static>true</static>
            <respondable>false</respondable></switches></dynamics>
        <joint>
            <common><name>motor</name>
                <localFrame><position>0 0 0.1</position><euler>AXIS</euler></localFrame>
            </common>
            <type>revolute</type><mode>force</mode>
            <minPosition>-180</minPosition><range>360</range><position>0</position>
            <switches><cyclic>true</cyclic></switches>
            <dynamics><maxForce>MAXFORCE</maxForce><targetVelocity>90</targetVelocity>
                <switches><motorEnabled>true</motorEnabled>
                    <controlLoopEnabled>false</controlLoopEnabled></switches>
            </dynamics>
            <shape>
                <common><name>arm</name>
                    <localFrame><position>0.2 0 0</position><euler>0 0 0</euler></localFrame>
                </common>
                <primitive><type>cuboid</type><size>0.4 0.04 0.04</size></primitive>
                <dynamics><mass>1</mass>
                    <principalMomentOfInertia>0.0001 0.014 0.014</principalMomentOfInertia>
                    <switches><static>false</static><respondable>false</respondable></switches>
                </dynamics>
            </shape>
        </joint>
    </shape>
</CoppeliaSim>
"""


def _scene(tmp_path, axis: str, max_force: float):
    path = tmp_path / "arm.simscene.xml"
    path.write_text(ARM_XML.replace("AXIS", axis).replace("MAXFORCE", str(max_force)))
    return path


def test_xml_velocity_motor_turns_at_its_target_speed_in_radians(tmp_path):
    """targetVelocity 90 (°/s in the file) is pi/2 rad/s: a quarter turn a second about a
    vertical axis, where gravity neither helps nor hinders."""
    path = _scene(tmp_path, "0 0 0", 10)
    (joint,) = [o.joint for o in load_scene(path).objects if o.joint is not None]
    assert joint.target_velocity == pytest.approx(math.pi / 2)
    with World(path) as w:
        w.advance(2.0)
        turned = w.joint_position("motor")
    assert turned == pytest.approx(math.pi, abs=0.05)  # 2 s at 90°/s, from 0


def test_new_max_force_reaches_a_running_velocity_motor(tmp_path):
    """An arm on a horizontal axis held turning slowly by a strong motor: with the motor's
    max force set to zero mid-run, gravity takes over and the arm swings down far faster
    than the commanded speed. (The same call must not change the motor's target.)"""
    path = _scene(tmp_path, "90 0 0", 50)
    with World(path) as w:
        w.set_joint_target_velocity("motor", 0.2)
        w.advance(0.5)
        held = w.joint_position("motor")
        w.advance(0.5)
        assert (w.joint_position("motor") - held) == pytest.approx(0.1, abs=0.02)
        w.set_joint_max_force("motor", 0.0)
        start = w.joint_position("motor")
        w.advance(0.5)
        moved = abs(w.joint_position("motor") - start)
    assert moved > 0.5, "the motor kept its old force after set_joint_max_force"
