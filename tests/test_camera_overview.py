"""sims/camera.py: the overview camera frames the whole trajectory; the trail lands on it."""

from __future__ import annotations

import numpy as np
import pybullet as p

from sims.camera import draw_trail, overview_for, project

FOV, NEAR, FAR = 50.0, 0.01, 20.0


def _matrices(ov, width, height):
    view = p.computeViewMatrixFromYawPitchRoll(ov.target, ov.distance, ov.yaw, ov.pitch, 0.0, 2)
    proj = p.computeProjectionMatrixFOV(FOV, width / height, NEAR, FAR)
    return view, proj


def test_the_target_projects_to_the_middle_of_the_frame():
    ov = overview_for(np.array([[0.0, 0.0, 0.05], [1.0, 0.5, 0.05]]), 30.0, FOV, 4 / 3)
    view, proj = _matrices(ov, 640, 480)
    xy, front = project(np.array([ov.target]), view, proj, 640, 480)
    assert front.all() and np.allclose(xy[0], [320, 240], atol=0.5)


def test_every_position_of_a_long_slow_drive_is_inside_the_fixed_frame():
    # a cart creeping 3 m in a curve: the chase camera would keep it centred (no visible motion)
    t = np.linspace(0, 1, 200)
    path = np.stack([3 * t, 0.8 * np.sin(3 * t), np.full_like(t, 0.05)], axis=1)
    for width, height in ((480, 360), (1280, 720), (360, 640)):
        ov = overview_for(path, -60.0, FOV, width / height)
        view, proj = _matrices(ov, width, height)
        xy, front = project(path, view, proj, width, height)
        assert front.all()
        assert (xy[:, 0] > 0).all() and (xy[:, 0] < width).all()
        assert (xy[:, 1] > 0).all() and (xy[:, 1] < height).all()
        spread = xy.max(axis=0) - xy.min(axis=0)
        # the motion crosses most of the frame in one direction at least (a chase camera: 0)
        assert max(spread[0] / width, spread[1] / height) > 0.6


def test_trail_is_drawn_along_the_path_only():
    path = np.array([[x, 0.0, 0.05] for x in np.linspace(-0.5, 0.5, 20)])
    ov = overview_for(path, 0.0, FOV, 4 / 3)
    view, proj = _matrices(ov, 320, 240)
    blank = np.zeros((240, 320, 3), np.uint8)
    drawn = draw_trail(blank, path, view, proj)
    assert blank.sum() == 0  # the input is not drawn on
    changed = np.argwhere(drawn.any(axis=2))
    assert len(changed) > 100
    xy, _ = project(path * [1, 1, 0], view, proj, 320, 240)  # drawn on the floor
    rows = changed[:, 0]
    assert abs(np.median(rows) - np.median(xy[:, 1])) < 6  # on the path's row, not elsewhere
    assert draw_trail(blank, path[:1], view, proj).sum() == 0  # one point: nothing to draw
    again = draw_trail(np.zeros_like(blank), path, view, proj)
    assert np.array_equal(again, drawn)  # deterministic
