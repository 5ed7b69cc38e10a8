# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic sketches with known answers: 3D curves projected through a known camera."""

import numpy as np

from Sketch2CADWorkbench.brep.geometry import bezier

SIZE = (40.0, 30.0, 20.0)  # the `box` fixture's sides, centred on the origin
FRONT_Y = -SIZE[1] / 2  # its front face
TOP_Z = SIZE[2] / 2  # its top face
# a quadrilateral on the box's top face
QUAD = np.array([[-9, -6, TOP_Z], [7, -7, TOP_Z], [8, 4, TOP_Z], [-8, 6, TOP_Z]])


def face_towards(solid, normal):
    return next(f for f in solid.Faces() if np.dot(f.normalAt().toTuple(), normal) > 0.999)


def stroke(camera, a, b, n=20, noise=0.0, rng=None):
    """The projection of the 3D segment a-b as a polyline, with optional pixel noise."""
    pts = camera.project(np.linspace(np.asarray(a, float), np.asarray(b, float), n))[0]
    if noise:
        pts = pts + rng.normal(0, noise, pts.shape)
    return pts


def curve_stroke(camera, pts3d, noise=0.0, rng=None):
    pts = camera.project(np.asarray(pts3d, float))[0]
    if noise:
        pts = pts + rng.normal(0, noise, pts.shape)
    return pts


def hand_drawn(points: np.ndarray, rng: np.random.Generator, sigma: float) -> np.ndarray:
    """A projected curve (K, 2) as datagen/strokes.py's hand draws it: each end off by
    Gaussian noise (`sigma` px per axis), the displacement spread linearly along it."""
    p = np.asarray(points, float)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    t = (arc / arc[-1])[:, None]
    return p + (1 - t) * rng.normal(0, sigma, 2) + t * rng.normal(0, sigma, 2)


def polygon_strokes(camera, poly, noise=0.0, rng=None):
    return [
        stroke(camera, poly[i], poly[(i + 1) % len(poly)], noise=noise, rng=rng)
        for i in range(len(poly))
    ]


def circle3d(center, radius, n=72):
    t = np.linspace(0, 2 * np.pi, n)
    return np.asarray(center, float) + radius * np.stack([np.cos(t), np.sin(t), 0 * t], axis=1)


def edge_strokes(camera, face, offset=(0.0, 0.0, 0.0)):
    """The face's straight edges, translated by `offset`, as strokes."""
    off = np.asarray(offset, float)
    return [
        stroke(
            camera, np.array(e.startPoint().toTuple()) + off, np.array(e.endPoint().toTuple()) + off
        )
        for e in face.Edges()
    ]


def prism_sketch(camera, base, height, sign, noise=0.0, rng=None):
    """The prism on polygon `base` (`sign` +1: up from it, -1: down into it): the start
    outline (label 0), the end outline (2) and the side edges (1)."""
    top = base + np.array([0, 0, sign * height])
    start, end = (base, top) if sign > 0 else (top, base)
    strokes = polygon_strokes(camera, start, noise, rng) + polygon_strokes(camera, end, noise, rng)
    labels = [0] * len(start) + [2] * len(end)
    for a, b in zip(start, end, strict=False):
        strokes.append(stroke(camera, a, b, noise=noise, rng=rng))
        labels.append(1)
    return strokes, labels


def sweep_sketch(camera, c0, r0, r1, height, sign, rh_profile=None):
    """Circles at both ends and the two silhouettes (in the plane facing the camera)."""
    c0 = np.asarray(c0, float)
    c1 = c0 + np.array([0, 0, sign * height])
    start, end = (
        (circle3d(c0, r0), circle3d(c1, r1)) if sign > 0 else (circle3d(c1, r1), circle3d(c0, r0))
    )
    strokes = [curve_stroke(camera, start), curve_stroke(camera, end)]
    labels = [0, 2]
    f = np.array(camera.direction)
    side = np.cross([0, 0, 1.0], f)
    side /= np.linalg.norm(side)
    for s in (1, -1):
        if rh_profile is None:
            pts = np.linspace(c0 + s * r0 * side, c1 + s * r1 * side, 30)
        else:
            rh = bezier(np.array(rh_profile), np.linspace(0, 1, 40))
            pts = c0 + s * rh[:, :1] * side + sign * rh[:, 1:2] * np.array([0, 0, 1.0])
        strokes.append(curve_stroke(camera, pts))
        labels.append(1)
    return strokes, labels
