"""Proximity sensors cast in batches and kept (sims/proximity.py) read what casting each sensor
alone at the read gives, in both of the World's sensor modes; the explicit-handling flag that
decides CoppeliaSim's main-script handling is read from both scene formats."""

from __future__ import annotations

import numpy as np
import pytest
from shared_data import shared

from sims.lua.host import ScriptHost
from sims.quiet import pybullet as p
from sims.remote_api import commands as cmd
from sims.scene.load import load_scene
from sims.scene.xml_write import write_xml
from sims.world import World


def reference(world: World, name: str) -> list:
    """Each ray's hit as the code before the cache computed it: the sensor's pose from
    ``object_pose``, its rays into the world by one matrix product, one batch for this sensor
    alone; (distance, point, normal in the sensor frame, body, link) or None."""
    rays = world.proximity_sensors.by_name[name].rays
    ends = np.array([a for a, _ in rays] + [b for _, b in rays], float)
    origin, orn = world.object_pose(name)
    rot = p.getMatrixFromQuaternion(orn)
    pts = (ends @ np.array(rot, float).reshape(3, 3).T + np.array(origin, float)).tolist()
    n = len(rays)
    out = []
    for h in p.rayTestBatch(pts[:n], pts[n:], physicsClientId=world.client_id):
        if h[0] < 0:
            out.append(None)
            continue
        d = [h[3][k] - origin[k] for k in range(3)]
        point = tuple(sum(rot[3 * r + c] * d[r] for r in range(3)) for c in range(3))
        normal = tuple(sum(rot[3 * r + c] * h[4][r] for r in range(3)) for c in range(3))
        out.append((float(np.sqrt(sum(v * v for v in d))), point, normal, h[0], h[1]))
    return out


def nearest(hits: list):
    found = [h for h in hits if h is not None]
    return min(found, key=lambda h: h[0]) if found else None


def same(a, b) -> bool:
    """Equal hits, to the last bit: distance, point, normal, body and link."""
    return a == b


@pytest.fixture(scope="module")
def pioneer():
    return load_scene(shared("data", "scenes", "course", "Pioneer_p3dx.ttt"))


def test_lazy_readings_equal_casting_each_sensor_at_its_read(pioneer):
    """Over 3 s of the Pioneer scene driven by its own scripts, every sensor read (in changing
    orders, so that batches of the previous pass's reads are used) equals casting it alone."""
    with World(pioneer) as world:
        names = list(world.proximity_sensors.by_name)
        host = ScriptHost(world)
        checked = detected = 0
        for k in range(60):
            world.advance(0.05)
            order = names if k % 2 else names[::-1]
            order = order[k % 3 :] + order[: k % 3]  # some passes read fewer sensors
            for name in order:
                want = reference(world, name)
                got = world.sensor_hits(name)
                assert len(got) == len(want)
                assert all(same(g, w) for g, w in zip(got, want, strict=True)), (k, name)
                assert same(world.nearest_hit(name), nearest(want)), (k, name)
                checked += 1
                detected += world.nearest_hit(name) is not None
        host.close()
    assert checked == 60 * len(names) and detected > 100  # the sonars saw walls and robots


def test_remote_api_reading_is_unchanged_by_a_second_read_and_follows_a_move(pioneer):
    """The remote API's reading (detected object's handle included) of a cached sensor; moving
    the robot between steps makes the next read cast again."""
    with World(pioneer) as world:
        world.advance(1.0)
        robot = world.find("Pioneer_p3dx#0")
        sonar = world.find("Pioneer_p3dx_ultrasonicSensor5#0")
        first = cmd.read_proximity_sensor(world, sonar)
        assert cmd.read_proximity_sensor(world, sonar) == first
        pos, _orn = cmd.frame(world, robot)
        cmd.set_frame(world, robot, -1, (pos[0] + 0.3, pos[1] - 0.2, pos[2]), None)
        moved = world.nearest_hit("Pioneer_p3dx_ultrasonicSensor5#0")
        assert same(moved, nearest(reference(world, "Pioneer_p3dx_ultrasonicSensor5#0")))
        assert cmd.read_proximity_sensor(world, sonar) != first


def test_main_script_mode_handles_every_pass_and_serves_that_result(pioneer):
    """sensors="main-script": nothing is detected before the first pass ends; at a pass end
    every sensor holds what a cast then gives; reads between passes return it unchanged (as
    CoppeliaSim's readProximitySensor returns the main script's last handling)."""
    with World(pioneer, sensors="main-script") as world:
        sensors = world.proximity_sensors
        names = list(sensors.by_name)
        assert sensors.pass_steps == 10 and not sensors.explicit
        assert all(world.nearest_hit(n) is None for n in names)
        world.step(9)
        assert all(world.nearest_hit(n) is None for n in names) and sensors.handled == 0
        for _ in range(20):
            world.step(10 - world.steps % 10)
            handled = {n: world.nearest_hit(n) for n in names}
            for name in names:
                assert same(handled[name], nearest(reference(world, name))), name
            world.step(3)  # between passes: the last handling is read
            assert {n: world.nearest_hit(n) for n in names} == handled
        assert sensors.handled == world.steps // 10
        assert any(h is not None for h in handled.values())


def test_main_script_mode_leaves_explicit_sensors_to_the_scripts():
    """Scene_CheckPoint1's two sensors have explicit handling: the main script does not handle
    them, so they detect nothing until handled (sim.handleProximitySensor)."""
    with World(
        shared("data", "scenes", "course", "Scene_CheckPoint1.ttt"), sensors="main-script"
    ) as world:
        sensors = world.proximity_sensors
        assert sensors.explicit == set(sensors.by_name) and len(sensors.explicit) == 2
        world.step(20)
        assert all(world.nearest_hit(n) is None for n in sensors.by_name)
        for name in sensors.by_name:
            assert same(sensors.handle(name), nearest(reference(world, name)))
            assert world.nearest_hit(name) == sensors.handle(name)


def test_explicit_handling_is_read_from_ttt_and_xml(tmp_path):
    """The flag: ``Pr4`` bit 7 in a .ttt, ``switches/explicitHandling`` in XML (as
    CoppeliaSim's CProxSensor::serialize writes them); written back and read again."""
    ttt = load_scene(shared("data", "scenes", "course", "Scene_CheckPoint1.ttt"))
    flags = {o.name: o.proximity_sensor.explicit for o in ttt.objects if o.proximity_sensor}
    assert flags and all(flags.values())
    pioneer = load_scene(shared("data", "scenes", "course", "Pioneer_p3dx.ttt"))
    assert not any(o.proximity_sensor.explicit for o in pioneer.objects if o.proximity_sensor)
    path = tmp_path / "checkpoint.simscene.xml"
    path.write_text(write_xml(ttt), encoding="utf-8")
    assert "<explicitHandling>true</explicitHandling>" in path.read_text(encoding="utf-8")
    xml = load_scene(path)
    assert {o.name: o.proximity_sensor.explicit for o in xml.objects if o.proximity_sensor} == flags


def test_an_unknown_sensor_mode_is_refused():
    with pytest.raises(ValueError, match="sensors='eager' not understood"):
        World("2w1a", sensors="eager")


SENSING = """
function sysCall_sensing()
  local s = sim.getObjectHandle('Pioneer_p3dx_ultrasonicSensor5#0')
  local r, d = sim.readProximitySensor(s)
  local hr, hd = sim.handleProximitySensor(s)
  local ar, ad, _, obj = sim.handleProximitySensor(sim.handle_all)
  local er = sim.handleProximitySensor(sim.handle_all_except_explicit)
  sim.setFloatSignal('read', r == 1 and d or -1)
  sim.setFloatSignal('handled', hr == 1 and hd or -1)
  sim.setFloatSignal('all', ar == 1 and ad or -1)
  sim.setIntegerSignal('all_object', obj)
  sim.setIntegerSignal('except_explicit', er)
end
"""


def test_scripts_handle_sensors_one_or_all_as_in_coppeliasim(pioneer):
    """sim.handleProximitySensor: one sensor (the same as reading the main script's handling,
    nothing having moved since), or every sensor reporting the nearest detection of all."""
    import dataclasses

    from sims.scene.model import Script

    robot = next(o.handle for o in pioneer.objects if o.name == "Pioneer_p3dx#0")
    scene = dataclasses.replace(pioneer, scripts=(Script("child", SENSING, object=robot),))
    with World(scene, sensors="main-script") as world:
        host = ScriptHost(world)
        host.start()
        world.advance(2.0)
        assert host.errors == []
        got = host.signals["float"]
        nearest_all = min(
            (h for n in world.proximity_sensors.by_name if (h := world.nearest_hit(n))),
            key=lambda h: h[0],
        )
        assert got["read"] == got["handled"] != -1
        assert got["all"] == pytest.approx(nearest_all[0], abs=1e-12) and got["all"] <= got["read"]
        assert host.signals["int"]["all_object"] > 0
        assert host.signals["int"]["except_explicit"] == 1  # no sensor is explicit here
        host.close()
