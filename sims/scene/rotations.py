"""Rotation helpers shared by the scene readers (quaternions are (x, y, z, w))."""

from __future__ import annotations

import math

import numpy as np


def euler_quat(angles: tuple[float, ...]) -> tuple[float, float, float, float]:
    """CoppeliaSim's Euler angles (radians) as a quaternion: ``R = Rx(alpha) Ry(beta) Rz(gamma)``
    (checked against the FANUC scene saved both as XML and as ``.ttt``)."""
    out = (0.0, 0.0, 0.0, 1.0)
    for axis, angle in enumerate(angles):
        q = [0.0, 0.0, 0.0, math.cos(angle / 2)]
        q[axis] = math.sin(angle / 2)
        out = quat_mul(out, (q[0], q[1], q[2], q[3]))
    return out


def euler_degrees(q: tuple[float, float, float, float]) -> tuple[float, float, float]:
    """CoppeliaSim's Euler angles (alpha, beta, gamma) of a quaternion, in degrees:
    ``R = Rx(alpha) Ry(beta) Rz(gamma)``."""
    x, y, z, w = q
    r00 = 1 - 2 * (y * y + z * z)
    r01 = 2 * (x * y - z * w)
    r02 = 2 * (x * z + y * w)
    r12 = 2 * (y * z - x * w)
    r22 = 1 - 2 * (x * x + y * y)
    beta = math.atan2(r02, math.hypot(r00, r01))  # precise near +-90° too, unlike asin
    if math.hypot(r00, r01) > 1e-9:
        alpha = math.atan2(-r12, r22)
        gamma = math.atan2(-r01, r00)
    else:  # gimbal lock: put all of the rotation about x
        r21 = 2 * (y * z + x * w)
        r11 = 1 - 2 * (x * x + z * z)
        alpha = math.atan2(r21, r11)
        gamma = 0.0
    return (math.degrees(alpha), math.degrees(beta), math.degrees(gamma))


def quat_mul(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float, float]:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def matrix_quat(m: np.ndarray) -> tuple[float, float, float, float]:
    """Quaternion of a rotation matrix."""
    t = m[0, 0] + m[1, 1] + m[2, 2]
    if t > 0:
        s = math.sqrt(t + 1.0) * 2
        return ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4)
    i = int(np.argmax([m[0, 0], m[1, 1], m[2, 2]]))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k]) * 2
    q = [0.0, 0.0, 0.0, (m[k, j] - m[j, k]) / s]
    q[i] = s / 4
    q[j] = (m[j, i] + m[i, j]) / s
    q[k] = (m[k, i] + m[i, k]) / s
    return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def principal_axes(matrix: tuple[float, ...]) -> tuple[tuple[float, float, float], tuple]:
    """Principal moments and the quaternion of their axes, from a symmetric 3x3 matrix."""
    vals, vecs = np.linalg.eigh(np.array(matrix, dtype=float).reshape(3, 3))
    if np.linalg.det(vecs) < 0:
        vecs[:, 0] *= -1
    return (float(vals[0]), float(vals[1]), float(vals[2])), matrix_quat(vecs)
