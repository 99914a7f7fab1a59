"""Keyframe reduction: the fewest samples whose linear interpolation stays within a tolerance.

A replay's animation has one sample per recorded data sample (``fps`` per simulated second),
but a robot at rest or moving steadily needs few of them. :func:`reduce_track` keeps the first
and last sample and, walking forward, the farthest next sample such that interpolating between
the two kept ones misses no dropped sample by more than the tolerance: positions by
``POSITION_TOLERANCE`` metres, rotations by ``ROTATION_TOLERANCE`` radians (the angle between
the slerped and the recorded orientation, as glTF's LINEAR interpolation of rotations and
three.js play it). The result depends on the samples alone, so the bytes are reproducible.

Written here rather than taken from a library: glTF tools reduce keyframes (gltfpack,
gltf-transform's ``resample``) on the JavaScript or C++ side only, and this is ~60 lines.
"""

from __future__ import annotations

import numpy as np

POSITION_TOLERANCE = 0.0005  # m
ROTATION_TOLERANCE = np.radians(0.25)  # rad


def continuous(quats: np.ndarray) -> np.ndarray:
    """Quaternions (N×4, x y z w) with signs flipped so that neighbours are on one side
    (q and -q are one rotation; interpolation must not take the long way round)."""
    q = np.array(quats, dtype=np.float64, copy=True)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    for i in range(1, len(q)):
        if float(np.dot(q[i - 1], q[i])) < 0:
            q[i] = -q[i]
    return q


def _lerp_error(values: np.ndarray, i: int, j: int) -> float:
    span = values[i + 1 : j]
    f = (np.arange(i + 1, j) - i)[:, None] / (j - i)
    guess = values[i] * (1 - f) + values[j] * f
    return float(np.max(np.linalg.norm(span - guess, axis=1)))


def _slerp_error(q: np.ndarray, i: int, j: int) -> float:
    a, b = q[i], q[j]
    f = (np.arange(i + 1, j) - i) / (j - i)
    dot = float(np.clip(np.dot(a, b), -1.0, 1.0))
    theta = np.arccos(dot)
    if theta < 1e-9:
        guess = np.repeat(a[None, :], len(f), axis=0)
    else:
        s = np.sin(theta)
        guess = (np.sin((1 - f) * theta) / s)[:, None] * a + (np.sin(f * theta) / s)[:, None] * b
    guess /= np.linalg.norm(guess, axis=1, keepdims=True)
    cos = np.clip(np.abs(np.sum(guess * q[i + 1 : j], axis=1)), 0.0, 1.0)
    return float(np.max(2 * np.arccos(cos)))


def reduce_track(values: np.ndarray, tolerance: float, rotation: bool = False) -> list[int]:
    """Indices of the samples to keep (always the first and the last)."""
    n = len(values)
    if n <= 2:
        return list(range(n))
    error = _slerp_error if rotation else _lerp_error
    keep = [0]
    i = 0
    while i < n - 1:
        j = i + 1
        while j + 1 < n and error(values, i, j + 1) <= tolerance:
            j += 1
        keep.append(j)
        i = j
    return keep


def is_still(values: np.ndarray, tolerance: float, rotation: bool = False) -> bool:
    """Every sample within ``tolerance`` of the first one: a static node, no channel."""
    if rotation:
        cos = np.clip(np.abs(values @ values[0]), 0.0, 1.0)
        return bool(np.all(2 * np.arccos(cos) <= tolerance))
    return bool(np.all(np.linalg.norm(values - values[0], axis=1) <= tolerance))
