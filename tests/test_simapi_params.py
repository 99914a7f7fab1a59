"""Scene settings and sensor buffers scripts read and change: gravity (a scene file's own and
``sim.setArrayParam``), vision sensors' depth (``sim.getVisionSensorDepth`` and the 3.x
``getVisionSensorDepthBuffer``), auxiliary consoles. Each checked by what CoppeliaSim would
show: how a body moves, how far the surface under a sensor is."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_zmq_scripts import _run

from sims.scene.resolve import BUNDLED_SCENES

IMAGES = BUNDLED_SCENES / "messaging" / "synchronousImageTransmissionViaRemoteApi.simscene.xml"


def _with_gravity(tmp_path: Path, gravity: str) -> Path:
    """The pController scene saved with another gravity."""
    text = (BUNDLED_SCENES / "messaging" / "pControllerViaRemoteApi.simscene.xml").read_text()
    scene = tmp_path / "moon.simscene.xml"
    scene.write_text(text.replace("<gravity>0 0 -9.81</gravity>", f"<gravity>{gravity}</gravity>"))
    return scene


def test_a_scene_files_gravity_is_the_worlds_and_scripts_can_change_it(tmp_path):
    scene = _with_gravity(tmp_path, "0 0 -1.62")
    result, lines, err = _run(
        tmp_path,
        """
        show(g=sim.getArrayParam(sim.arrayparam_gravity))
        sim.setArrayParam(sim.arrayparam_gravity, [0, 0, 4.0])
        show(g=sim.getArrayParam(sim.arrayparam_gravity))
        """,
        scene=str(scene),
    )
    assert result.ok, (result.message, err)
    assert lines[0]["g"] == pytest.approx([0, 0, -1.62]) and lines[1]["g"] == [0, 0, 4.0]


def test_gravity_set_by_a_script_moves_the_robot(tmp_path):
    """Upward gravity from t = 0: the 2W1A leaves the floor, ½·g·t² in 0.5 s (no contact)."""
    result, lines, err = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        sim.setStepping(True)
        sim.startSimulation()
        z0 = sim.getObjectPosition(body, sim.handle_world)[2]
        sim.setArrayParam(sim.arrayparam_gravity, [0, 0, 2.0])
        while sim.getSimulationTime() < 0.5 - 1e-9:
            sim.step()
        show(dz=sim.getObjectPosition(body, sim.handle_world)[2] - z0)
        sim.stopSimulation()
        """,
    )
    assert result.ok, (result.message, err)
    assert lines[0]["dz"] == pytest.approx(0.5 * 2.0 * 0.5**2, rel=0.2)


def test_depth_of_a_vision_sensor_is_the_distance_to_the_surface_under_it(tmp_path):
    """The sensor at z = 0.9 looks straight down: its centre pixel's depth in metres is the
    distance a ray cast from it meets, and the 0..1 buffer is that between its clipping planes
    (0.01, 3.0); the 3.x buffer and the metres flag agree with it."""
    import pybullet as p

    from sims.world import World

    result, lines, err = _run(
        tmp_path,
        """
        import struct
        s = sim.getObject('/VisionSensor')
        raw, res = sim.getVisionSensorDepth(s)
        m, _ = sim.getVisionSensorDepth(s, 1)
        unit = struct.unpack(f'<{res[0] * res[1]}f', raw)
        meters = struct.unpack(f'<{res[0] * res[1]}f', m)
        i = (res[1] // 2) * res[0] + res[0] // 2
        old = sim.getVisionSensorDepthBuffer(s)
        flagged = sim.getVisionSensorDepthBuffer(s + sim.handleflag_depthbuffermeters)
        show(res=res, unit=unit[i], meters=meters[i], old=old[i], flagged=flagged[i],
             n=len(old), corner=meters[0])
        """,
        scene=str(IMAGES),
    )
    assert result.ok, (result.message, err)
    got = lines[0]
    with World(str(IMAGES)) as world:
        (x, y, z), _ = world.object_pose("VisionSensor")
        hit = p.rayTest((x, y, z - 0.011), (x, y, z - 3.0), physicsClientId=world.client_id)
        surface = 0.011 + hit[0][2] * (3.0 - 0.011)
    assert got["res"] == [128, 128] and got["n"] == 128 * 128
    assert got["meters"] == pytest.approx(surface, abs=0.01)
    assert got["unit"] == pytest.approx((got["meters"] - 0.01) / (3.0 - 0.01), abs=1e-5)
    assert got["old"] == pytest.approx(got["unit"]) and got["flagged"] == pytest.approx(
        got["meters"]
    )


def test_auxiliary_console_lines_go_where_the_status_bar_goes(tmp_path):
    result, lines, err = _run(
        tmp_path,
        """
        h = sim.auxiliaryConsoleOpen('Log', 10, 0)
        sim.auxiliaryConsolePrint(h, 'a=1\\nb=')
        sim.auxiliaryConsolePrint(h, '2\\n')
        show(shown=sim.auxiliaryConsoleShow(h, True), closed=sim.auxiliaryConsoleClose(h),
             again=sim.auxiliaryConsoleClose(h))
        """,
    )
    assert result.ok, (result.message, err)
    assert lines[0] == {"shown": 1, "closed": 1, "again": 0}
    assert [x for x in result.statusbar if x.startswith("Log:")] == ["Log: a=1", "Log: b=2"]
    assert "[sim status bar] Log: b=2" in err
