# SPDX-License-Identifier: LGPL-2.1-or-later
"""Informative views of a sketched operation (paper, "Sketch rendering").

A view looks at the base face f from 20 to 80 degrees off its normal (so that it sees
f's front: direction . n_f < 0), from a random azimuth, mostly with world z upwards
give or take a small roll. Its square frustum is centred on the sketch curves and is a
random 1.6 to 2.4 times their projected extent, built by the same `context_camera` the
interpretation uses at test time with a factor of 2.

Occlusion filter, and which solid it is tested against: a view is rejected when more
than 20% of the relevant curve is hidden.

* Extrusion: the relevant curve is the offset curve (the moved face's edges), tested
  against the result solid. For a pocket (d < 0) the offset curve lies inside the
  context solid, so against the context it would always count as hidden; in the result
  it is the pocket's floor outline, and a view that cannot see into the pocket is
  exactly the unnatural one. For a pad the moved face faces the camera, so the result
  does not hide its own outline.
* Bevel, add/subtract, sweep: the relevant curve is the base curve on f (l, or the
  polygon or circle on f), tested against the context solid. The new primitive always
  hides part of its own base curve (the back edges of a prism), yet a designer draws
  those lines anyway; what makes a view unnatural is existing geometry standing in the
  way of the place being drawn on, which is what the context (also what the network
  sees as D and N) shows.

Beyond the paper's filter, the base face f itself must cover at least MIN_FACE_PIXELS
pixels of the context maps: an extrusion's offset curve can be in full view while f is
hidden in the context (a pad growing out from under an overhang), and such a sample
would ask the network to find a face it cannot see.
"""

from __future__ import annotations

import numpy as np

from Sketch2CADWorkbench.brep.geometry import plane_basis, polyline_length, resample_polyline
from Sketch2CADWorkbench.brep.protocol import OperatorType, per_operator
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.frustum import context_camera
from Sketch2CADWorkbench.render.maps import ContextMaps
from Sketch2CADWorkbench.render.visibility import visible_fraction
from Sketch2CADWorkbench.sketch.curves import Curve
from Sketch2CADWorkbench.sketch.visible import DEPTH_SLACK_PX

ANGLE_RANGE_DEG = (20.0, 80.0)
SCALE_RANGE = (1.6, 2.4)
MAX_OCCLUSION = 0.2
ROLL_SD_DEG = 8.0  # the usual small tilt of the up vector about the view direction
FREE_ROLL_SHARE = 0.1  # views with any roll at all
OCCLUSION_SAMPLES = 200  # points along the relevant curve for the occlusion test
MIN_FACE_PIXELS = 100  # of the base face in the context maps (0.15% of 256 x 256)
# Which solid the occlusion filter tests each operator's relevant curve against (above).
OCCLUDED_BY = per_operator(
    {
        OperatorType.EXTRUDE: "result",
        OperatorType.BEVEL: "context",
        OperatorType.ADDSUB: "context",
        OperatorType.SWEEP: "context",
        OperatorType.SHELL: "context",
    },
    "datagen.views.OCCLUDED_BY",
)


def view_direction(
    rng: np.random.Generator, normal: np.ndarray, along: np.ndarray | None = None
) -> np.ndarray:
    """A unit view direction (into the scene) 20 to 80 degrees from -n_f, random azimuth;
    or, `along` given (a unit vector in f's plane: the tangent of the edge a profile is
    drawn across), the azimuth along it, either way, so that the profile's plane (normal
    to the edge) faces the view as a designer turns the model to draw it."""
    n = np.asarray(normal, float)
    if along is None:
        a, b = plane_basis(n)
        phi = rng.uniform(0, 2 * np.pi)
        w = np.cos(phi) * a + np.sin(phi) * b
    else:
        w = np.asarray(along, float) * (1.0 if rng.random() < 0.5 else -1.0)
    theta = np.radians(rng.uniform(*ANGLE_RANGE_DEG))
    return -(np.cos(theta) * n + np.sin(theta) * w)


def up_vector(rng: np.random.Generator, direction: np.ndarray) -> np.ndarray:
    """A world up vector for the view: world z (world y when looking almost straight up
    or down) rolled about the view direction by a small random angle, or, for
    FREE_ROLL_SHARE of the views, by any angle."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    up = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.95 else np.array([0.0, 1.0, 0.0])
    up = up - (up @ d) * d
    up /= np.linalg.norm(up)
    if rng.random() < FREE_ROLL_SHARE:
        roll = rng.uniform(-np.pi, np.pi)
    else:
        roll = np.radians(rng.normal(0.0, ROLL_SD_DEG))
    return np.cos(roll) * up + np.sin(roll) * np.cross(d, up)


def frame_curves(
    points: np.ndarray, direction: np.ndarray, up: np.ndarray, factor: float, size: int = 256
) -> OrthoCamera:
    """A square size x size view along `direction` centred on the points, `factor` times
    their projected extent (as the interpretation frames the context of a sketch).

    Args:
        points: (N, 3) curve points (mm, world).
        direction: unit view direction (world, into the scene).
        up: world vector that shows upwards.
        factor: frustum side over the points' larger projected extent.
        size: image side in pixels.
    """
    centre = np.asarray(points, float).mean(axis=0)
    probe = OrthoCamera(
        tuple(map(float, centre)),
        tuple(map(float, direction)),
        tuple(map(float, up)),
        float(np.ptp(points, axis=0).max() + 1e-6),
        size,
        size,
    )
    return context_camera(probe, probe.project(points)[0], factor, size)


def resample(curves: list[Curve], count: int = OCCLUSION_SAMPLES) -> np.ndarray:
    """About `count` points (N, 3) spread evenly by arc length over the curves."""
    pieces = [np.concatenate([c.points, c.points[:1]]) if c.closed else c.points for c in curves]
    total = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in pieces)
    out = []
    for p in pieces:
        length = polyline_length(p)
        out.append(resample_polyline(p, max(int(np.ceil(count * length / max(total, 1e-12))), 2)))
    return np.concatenate(out)


def relevant_visibility(curves: list[Curve], camera: OrthoCamera, maps: ContextMaps) -> float:
    """The visible share of the relevant curve in maps rendered with `camera`."""
    points = resample([c for c in curves if c.relevant])
    return visible_fraction(points, camera, maps, DEPTH_SLACK_PX * camera.pixel_size)


def is_informative(curves: list[Curve], camera: OrthoCamera, maps: ContextMaps) -> bool:
    """Whether at most MAX_OCCLUSION of the relevant curve is hidden in `maps` (rendered
    from the solid the module docstring names for the operator)."""
    return relevant_visibility(curves, camera, maps) >= 1.0 - MAX_OCCLUSION


def shows_base_face(maps: ContextMaps, face_index: int) -> bool:
    """Whether the base face (index into the context solid's Faces()) covers at least
    MIN_FACE_PIXELS pixels of the context maps."""
    return int(np.count_nonzero(maps.face_id == face_index)) >= MIN_FACE_PIXELS
