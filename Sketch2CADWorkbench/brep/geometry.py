# SPDX-License-Identifier: LGPL-2.1-or-later
"""Small numeric geometry shared by every layer (numpy only): cubic Beziers and an
orthonormal basis of a plane."""
import numpy as np


def bezier(ctrl: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points (K, D) of a cubic Bezier with control points (4, D) at parameters t (K,)."""
    t = np.asarray(t, float)[:, None]
    return ((1 - t) ** 3 * ctrl[0] + 3 * (1 - t) ** 2 * t * ctrl[1]
            + 3 * (1 - t) * t ** 2 * ctrl[2] + t ** 3 * ctrl[3])


def bezier_points(ctrl: np.ndarray, k: int) -> np.ndarray:
    """k points (K, D) of a cubic Bezier at evenly spaced parameters, both ends included."""
    return bezier(ctrl, np.linspace(0, 1, k))


def plane_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An orthonormal basis (u, v) of the plane with unit normal n, (u, v, n) right-handed;
    u is perpendicular to the x axis unless n is nearly along it (then to the y axis)."""
    u = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    return u, np.cross(n, u)
