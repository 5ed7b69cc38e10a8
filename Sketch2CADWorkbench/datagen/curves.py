# SPDX-License-Identifier: LGPL-2.1-or-later
"""The 3D sketch curves of an operation, labelled as the segmentation network learns them.

Labels (datagen/sample.py): extrude offset 1 / profile 0; bevel l 1 / l' 0; add/sub and
sweep start 0 / profile 1 / end 2, start and end ordered along the face normal.
"""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ..brep.faces import resolve_face
from ..brep.protocol import AddSubPrism, Bevel, Extrude, Mode, Operation, Sweep
from ..render.camera import OrthoCamera
from .sample import (BEVEL_L, BEVEL_L_PRIME, END, EXTRUDE_OFFSET, EXTRUDE_PROFILE, PROFILE,
                     START)


@dataclass(frozen=True)
class Curve:
    """One curve a designer draws as one stroke: a 3D polyline (K, 3) mm and its label.

    `base` marks the curve the occlusion test looks at (the offset curve for extrude,
    the base curve otherwise).
    """

    points: np.ndarray
    label: int
    closed: bool = False
    base: bool = False


def _edge_points(e: cq.Edge, n: int = 24) -> np.ndarray:
    k = 2 if e.geomType() == "LINE" else n
    return np.array([e.positionAt(t).toTuple() for t in np.linspace(0, 1, k)])


def _segment(a, b) -> np.ndarray:
    return np.stack([np.asarray(a, float), np.asarray(b, float)])


def _bezier(ctrl: np.ndarray, k: int = 32) -> np.ndarray:
    t = np.linspace(0, 1, k)[:, None]
    return ((1 - t) ** 3 * ctrl[0] + 3 * (1 - t) ** 2 * t * ctrl[1]
            + 3 * (1 - t) * t ** 2 * ctrl[2] + t ** 3 * ctrl[3])


def extrude_curves(solid: cq.Shape, op: Extrude) -> list[Curve]:
    rf = resolve_face(solid, op.face)
    shift = rf.normal * op.d
    out = [Curve(_edge_points(e) + shift, EXTRUDE_OFFSET, base=True) for e in rf.face.Edges()]
    for v in rf.face.Vertices():
        p = np.array(v.toTuple())
        out.append(Curve(_segment(p, p + shift), EXTRUDE_PROFILE))
    return out


def bevel_curves(solid: cq.Shape, op: Bevel) -> list[Curve]:
    ctrl = np.array(op.profile)
    crease = np.array(op.opposite) - np.array(op.corner)
    return [Curve(_bezier(ctrl), BEVEL_L, base=True), Curve(_bezier(ctrl) + crease, BEVEL_L_PRIME)]


def prism_curves(solid: cq.Shape, op: AddSubPrism) -> list[Curve]:
    rf = resolve_face(solid, op.face)
    base = np.array(op.polygon) + rf.offset
    far = base + rf.normal * op.d * op.mode.sign
    start, end = (far, base) if op.mode is Mode.SUBTRACT else (base, far)
    k = len(base)
    out = []
    for poly, label in ((start, START), (end, END)):
        on_face = poly is base
        out += [Curve(_segment(poly[i], poly[(i + 1) % k]), label, base=on_face) for i in range(k)]
    out += [Curve(_segment(start[i], end[i]), PROFILE) for i in range(k)]
    return out


def sweep_curves(solid: cq.Shape, op: Sweep, camera: OrthoCamera) -> list[Curve]:
    """Both circles and the two silhouettes of the swept shape for this view.

    The silhouettes are taken, as in the paper, as the profile c_p in the plane through
    the axis that faces the camera, on both sides of the axis.
    """
    rf = resolve_face(solid, op.face)
    c0 = np.array(op.center) + rf.offset
    axis = rf.normal * op.mode.sign
    c1 = c0 + axis * op.d
    side = np.cross(axis, camera.basis()[2])
    if np.linalg.norm(side) < 1e-6:  # looking along the axis: any side will do
        side = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    side /= np.linalg.norm(side)
    other = np.cross(axis, side)
    t = np.linspace(0, 2 * np.pi, 73)
    ring = np.cos(t)[:, None] * side + np.sin(t)[:, None] * other

    def circle(c, r):
        return c + r * ring

    base0, far1 = circle(c0, op.r0), circle(c1, op.r1)
    start, end = (far1, base0) if op.mode is Mode.SUBTRACT else (base0, far1)
    out = [Curve(start, START, closed=True, base=start is base0),
           Curve(end, END, closed=True, base=end is base0)]
    rh = _bezier(np.array(op.control_points(), float))
    for s in (1.0, -1.0):
        out.append(Curve(c0 + s * rh[:, :1] * side + rh[:, 1:2] * axis, PROFILE))
    return out


def operation_curves(solid: cq.Shape, op: Operation, camera: OrthoCamera) -> list[Curve]:
    """The labelled sketch curves of `op` applied to `solid` (its context), for `camera`."""
    if isinstance(op, Extrude):
        return extrude_curves(solid, op)
    if isinstance(op, Bevel):
        return bevel_curves(solid, op)
    if isinstance(op, AddSubPrism):
        return prism_curves(solid, op)
    return sweep_curves(solid, op, camera)
