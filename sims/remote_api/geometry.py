"""Rotations in CoppeliaSim's conventions, without numpy (the values are tiny and few).

CoppeliaSim reports an orientation as Euler angles (alpha, beta, gamma) with
``R = Rx(alpha) @ Ry(beta) @ Rz(gamma)``; quaternions are ``(qx, qy, qz, qw)`` like pybullet's.
"""

from __future__ import annotations

import math

Vec = tuple[float, float, float]
Quat = tuple[float, float, float, float]
Mat = tuple[Vec, Vec, Vec]


def quat_to_matrix(q: Quat) -> Mat:
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


def matrix_to_quat(m: Mat) -> Quat:
    """Rotation matrix to a unit quaternion ``(x, y, z, w)`` with ``w >= 0``."""
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        w, x = 0.25 * s, (m[2][1] - m[1][2]) / s
        y, z = (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        w, x = (m[2][1] - m[1][2]) / s, 0.25 * s
        y, z = (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        w, x = (m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s
        y, z = 0.25 * s, (m[1][2] + m[2][1]) / s
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
        w, x = (m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s
        y, z = (m[1][2] + m[2][1]) / s, 0.25 * s
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    return (x, y, z, w)


def matrix_to_euler(m: Mat) -> Vec:
    """Matrix to CoppeliaSim (alpha, beta, gamma): ``R = Rx(a) Ry(b) Rz(g)``."""
    sb = max(-1.0, min(1.0, m[0][2]))
    beta = math.asin(sb)
    if abs(sb) < 1.0 - 1e-9:
        alpha = math.atan2(-m[1][2], m[2][2])
        gamma = math.atan2(-m[0][1], m[0][0])
    else:  # gimbal lock: only alpha +/- gamma is defined; put it all in alpha
        alpha = math.atan2(m[2][1], m[1][1])
        gamma = 0.0
    return (alpha, beta, gamma)


def euler_to_matrix(e: Vec) -> Mat:
    a, b, g = e
    ca, sa, cb, sb, cg, sg = (
        math.cos(a),
        math.sin(a),
        math.cos(b),
        math.sin(b),
        math.cos(g),
        math.sin(g),
    )
    return (
        (cb * cg, -cb * sg, sb),
        (ca * sg + sa * sb * cg, ca * cg - sa * sb * sg, -sa * cb),
        (sa * sg - ca * sb * cg, sa * cg + ca * sb * sg, ca * cb),
    )


def quat_to_euler(q: Quat) -> Vec:
    return matrix_to_euler(quat_to_matrix(q))


def euler_to_quat(e: Vec) -> Quat:
    return matrix_to_quat(euler_to_matrix(e))


def transpose(m: Mat) -> Mat:
    return tuple(tuple(m[j][i] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def matmul(a: Mat, b: Mat) -> Mat:
    return tuple(
        tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3)
    )  # type: ignore[return-value]


def apply(m: Mat, v: Vec) -> Vec:
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))  # type: ignore[return-value]


def relative_position(p: Vec, ref_p: Vec, ref_q: Quat) -> Vec:
    """``p`` (world) expressed in the frame ``(ref_p, ref_q)``."""
    d = (p[0] - ref_p[0], p[1] - ref_p[1], p[2] - ref_p[2])
    return apply(transpose(quat_to_matrix(ref_q)), d)


def relative_matrix(q: Quat, ref_q: Quat) -> Mat:
    """Orientation ``q`` (world) expressed in the frame oriented ``ref_q``."""
    return matmul(transpose(quat_to_matrix(ref_q)), quat_to_matrix(q))


def to_world_position(p_rel: Vec, ref_p: Vec, ref_q: Quat) -> Vec:
    v = apply(quat_to_matrix(ref_q), p_rel)
    return (v[0] + ref_p[0], v[1] + ref_p[1], v[2] + ref_p[2])


def to_world_quat(m_rel: Mat, ref_q: Quat) -> Quat:
    return matrix_to_quat(matmul(quat_to_matrix(ref_q), m_rel))
