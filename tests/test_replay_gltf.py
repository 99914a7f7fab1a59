"""Replays as glTF (sims/replay/): what the file holds is what the run did.

A short recorded run becomes a .glb that the Khronos validator accepts without errors or
warnings, that is byte-identical when made twice, whose animation lasts exactly as long as the
run, and whose reduced keyframes, interpolated as glTF players do, stay within the stated
tolerances of every recorded sample. Static things have no channels; named objects are nodes.
"""

from __future__ import annotations

import gzip

import numpy as np
import pygltflib as G
import pytest
from gltf_kit import assert_valid

from sims.clip_spec import ClipSpec
from sims.recording import record
from sims.replay import keyframes as K
from sims.replay.export import ReplayTape, scene_glb
from sims.sources import load_plan_function, source_target

FPS = 10


def run(scenario: str, seconds: float, **params) -> tuple[ReplayTape, object]:
    spec = ClipSpec("t", scenario, seconds=seconds, params=params)
    plan = load_plan_function(source_target("scenario"))(spec)
    tape = ReplayTape(plan.follow)
    recording, _ = record(plan, fps=FPS, seconds=seconds, on_sample=tape.sample)
    return tape, recording


@pytest.fixture(scope="module")
def cart_run():
    tape, recording = run("cart-reverse", 3.0)
    return tape, recording, tape.glb(fps=FPS, speed=2, trail=True)


def read(data: bytes) -> G.GLTF2:
    return G.GLTF2.load_from_bytes(data)


def accessor(gltf: G.GLTF2, index: int) -> np.ndarray:
    acc = gltf.accessors[index]
    view = gltf.bufferViews[acc.bufferView]
    blob = gltf.binary_blob()
    types = {G.FLOAT: np.float32, G.SHORT: np.int16, G.UNSIGNED_SHORT: np.uint16}
    types[G.UNSIGNED_INT] = np.uint32
    width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc.type]
    raw = np.frombuffer(blob, types[acc.componentType], acc.count * width, view.byteOffset)
    values = raw.reshape(acc.count, width).astype(np.float64)
    if acc.normalized:
        values = np.maximum(values / 32767.0, -1.0)
    return values


def test_keyframes_keep_the_ends_and_stay_within_tolerance():
    rng = np.random.default_rng(7)
    walk = np.cumsum(rng.normal(0, 0.002, size=(300, 3)), axis=0)
    walk[100:180] = walk[100]  # a rest
    keep = K.reduce_track(walk, K.POSITION_TOLERANCE)
    assert keep[0] == 0 and keep[-1] == 299 and keep == sorted(set(keep))
    assert len(keep) < 300
    times = np.arange(300)
    guess = np.stack([np.interp(times, keep, walk[keep, i]) for i in range(3)], axis=1)
    assert np.linalg.norm(guess - walk, axis=1).max() <= K.POSITION_TOLERANCE + 1e-12
    assert K.reduce_track(np.zeros((50, 3)), 1e-3) == [0, 49]
    line = np.linspace([0, 0, 0], [1, 2, 3], 40)
    assert K.reduce_track(line, 1e-6) == [0, 39]


def test_a_run_becomes_a_valid_reproducible_gltf(cart_run, tmp_path):
    tape, recording, data = cart_run
    assert data == tape.glb(fps=FPS, speed=2, trail=True)  # same inputs, same bytes
    again, _ = run("cart-reverse", 3.0)
    assert again.glb(fps=FPS, speed=2, trail=True) == data  # a second run, same bytes
    path = tmp_path / "cart.glb"
    path.write_bytes(data)
    report = assert_valid(path)
    assert report["info"]["animationCount"] == 1
    gltf = read(data)
    names = [n.name for n in gltf.nodes]
    for name in ("replay", "scene", "cart", "left_wheel", "right_wheel", "camera", "trail"):
        assert name in names
    (anim,) = gltf.animations
    ends = [accessor(gltf, s.input)[-1, 0] for s in anim.samplers]
    assert max(ends) == pytest.approx(3.0, abs=1e-6)  # the run's length: 3 s simulated
    assert len(recording.rows) == 30 and len(tape.rows) == 31  # 30 samples + the end state
    animated = {gltf.nodes[c.target.node].name for c in anim.channels}
    assert "scene" not in animated and "camera" not in animated  # static: no channels
    assert {"cart", "left_wheel", "right_wheel"} <= animated
    info = gltf.nodes[names.index("replay")].extras["sitegen"]
    assert info["duration"] == 3.0 and info["follow"] == "cart" and info["speed"] == 2


def test_reduced_keyframes_replay_every_sample_within_tolerance(cart_run):
    tape, _, data = cart_run
    gltf = read(data)
    frames = np.stack(tape.rows)
    times = np.arange(len(frames)) / FPS
    checked = 0
    for channel in gltf.animations[0].channels:
        node = gltf.nodes[channel.target.node]
        k = tape.keys.index(tuple(node.extras["link"]))
        sampler = gltf.animations[0].samplers[channel.sampler]
        at, values = accessor(gltf, sampler.input)[:, 0], accessor(gltf, sampler.output)
        assert len(at) <= len(times)
        if channel.target.path == "translation":
            guess = np.stack([np.interp(times, at, values[:, i]) for i in range(3)], axis=1)
            error = np.linalg.norm(guess - frames[:, k, :3], axis=1).max()
            assert error <= K.POSITION_TOLERANCE + 1e-6
        else:
            truth = K.continuous(frames[:, k, 3:])
            for t, q in zip(times, truth, strict=True):
                j = min(int(np.searchsorted(at, t, side="right")), len(at) - 1)
                i = max(j - 1, 0)
                f = 0.0 if at[j] == at[i] else (t - at[i]) / (at[j] - at[i])
                a, b = values[i] / np.linalg.norm(values[i]), values[j] / np.linalg.norm(values[j])
                guess = _slerp(a, b, min(max(f, 0.0), 1.0))
                angle = 2 * np.arccos(min(1.0, abs(float(np.dot(guess, q)))))
                assert angle <= K.ROTATION_TOLERANCE + np.radians(0.01)  # + 16-bit rounding
        checked += 1
    assert checked >= 4


def _slerp(a: np.ndarray, b: np.ndarray, f: float) -> np.ndarray:
    if np.dot(a, b) < 0:
        b = -b
    theta = np.arccos(min(1.0, float(np.dot(a, b))))
    if theta < 1e-9:
        return a
    return (np.sin((1 - f) * theta) * a + np.sin(f * theta) * b) / np.sin(theta)


def test_rotations_are_16_bit_and_meshes_carry_colours(cart_run):
    _, _, data = cart_run
    gltf = read(data)
    outputs = [gltf.accessors[s.output] for s in gltf.animations[0].samplers]
    rotations = [a for a in outputs if a.type == "VEC4"]
    assert rotations and all(a.componentType == G.SHORT and a.normalized for a in rotations)
    colours = {
        tuple(round(c, 3) for c in m.pbrMetallicRoughness.baseColorFactor) for m in gltf.materials
    }
    assert len(colours) >= 4  # floor, tiles, walls, obstacles, cart, wheels...
    assert len(gzip.compress(data)) < 60_000


def test_scene_export_without_a_run(tmp_path):
    data = scene_glb("2w1a")
    assert data == scene_glb("2w1a")
    path = tmp_path / "2w1a.glb"
    path.write_bytes(data)
    report = assert_valid(path)
    assert report["info"]["animationCount"] == 0
    names = [n.name for n in read(data).nodes]
    assert "2W1A" in names and "LeftWheel" in names and "camera" in names
