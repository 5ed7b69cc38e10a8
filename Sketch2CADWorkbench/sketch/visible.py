# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parts of an operation's sketch curves a view sees: what a designer draws who
leaves the hidden lines out.

The paper's sketches draw every edge, and then a boss on f and a hole into f whose rim
is the boss's top outline draw the same lines in a parallel view (paper, Fig. 5b).
Seen, they differ: a boss hides the back of its own base outline, a hole's material
hides the near part of its floor outline, and so the lines one leaves out the other
draws.
"""

from __future__ import annotations

import numpy as np

from ..brep.geometry import polyline_length, resample_polyline
from ..render.camera import OrthoCamera
from ..render.maps import ContextMaps
from ..render.visibility import visible
from .curves import Curve

# A visible piece shorter than this (pixels) is a stub no one draws.
MIN_PIECE_PX = 6.0
# Lines are tested for visibility every this many pixels along their image.
VISIBILITY_STEP_PX = 1.0
# Depth slack of the visibility test, in pixel sizes (as datagen/views.py's filter).
DEPTH_SLACK_PX = 2.0


def visible_curves(curves: list[Curve], camera: OrthoCamera, maps: ContextMaps) -> list[Curve]:
    """Each visible run of each curve that spans at least MIN_PIECE_PX, as a curve of its
    own with the label of its line.

    Args:
        curves: the operation's sketch curves (sketch/curves.py).
        camera: the view.
        maps: rendered with `camera` from the model after the operation (so a new
            primitive hides its own back edges, and a hole's material its near ones).
    """
    tol = DEPTH_SLACK_PX * camera.pixel_size
    out = []
    for c in curves:
        pts = np.concatenate([c.points, c.points[:1]]) if c.closed else c.points
        span = polyline_length(camera.project(pts)[0])
        pts = resample_polyline(pts, max(int(np.ceil(span / VISIBILITY_STEP_PX)) + 1, 2))
        seen = visible(pts, camera, maps, tol)
        if seen.all():
            out.append(c)
            continue
        if c.closed:  # start the loop at a hidden point, so that no run wraps around
            k = int(np.argmin(seen))
            pts, seen = np.roll(pts[:-1], -k, axis=0), np.roll(seen[:-1], -k)
            pts, seen = np.concatenate([pts, pts[:1]]), np.concatenate([seen, seen[:1]])
        edges = np.flatnonzero(np.diff(np.concatenate([[0], seen.astype(int), [0]])))
        for a, b in zip(edges[::2], edges[1::2], strict=False):
            piece = pts[a:b]
            if len(piece) >= 2 and polyline_length(camera.project(piece)[0]) >= MIN_PIECE_PX:
                out.append(Curve(piece, c.label, relevant=c.relevant))
    return out
