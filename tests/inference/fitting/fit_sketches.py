# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic sketches with known answers: 3D curves projected through a known camera."""
import numpy as np


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


def polygon_strokes(camera, poly, noise=0.0, rng=None):
    return [stroke(camera, poly[i], poly[(i + 1) % len(poly)], noise=noise, rng=rng)
            for i in range(len(poly))]


def circle3d(center, radius, n=72):
    t = np.linspace(0, 2 * np.pi, n)
    return np.asarray(center, float) + radius * np.stack([np.cos(t), np.sin(t), 0 * t], axis=1)


def edge_strokes(camera, face, offset=(0.0, 0.0, 0.0)):
    """The face's straight edges, translated by `offset`, as strokes."""
    off = np.asarray(offset, float)
    return [stroke(camera, np.array(e.startPoint().toTuple()) + off,
                   np.array(e.endPoint().toTuple()) + off) for e in face.Edges()]
