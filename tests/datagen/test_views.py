# SPDX-License-Identifier: LGPL-2.1-or-later
"""Views: angles to the base face, natural up vectors, framing, and the occlusion filter."""

import cadquery as cq
import numpy as np
import pytest

from datagen.views import (
    frame_curves,
    is_informative,
    relevant_visibility,
    shows_base_face,
    up_vector,
    view_direction,
)
from Sketch2CADWorkbench.brep.protocol import AddSubPrism, FaceRef, Mode
from Sketch2CADWorkbench.sketch.curves import operation_curves


def test_view_directions_look_at_the_face_from_20_to_80_degrees():
    rng = np.random.default_rng(0)
    n = np.array([0.0, 0.6, 0.8])
    angles = []
    for _ in range(500):
        d = view_direction(rng, n)
        assert np.linalg.norm(d) == pytest.approx(1.0) and d @ n < 0
        angles.append(np.degrees(np.arccos(-d @ n)))
    assert 20.0 <= min(angles) < 22.0 and 78.0 < max(angles) <= 80.0


def test_up_vectors_are_mostly_world_up():
    rng = np.random.default_rng(1)
    d = np.array([0.6, -0.5, -0.62])
    d /= np.linalg.norm(d)
    ups = np.array([up_vector(rng, d) for _ in range(400)])
    assert np.allclose(ups @ d, 0.0, atol=1e-9)
    z_in_image = np.array([0, 0, 1.0]) - d[2] * d
    z_in_image /= np.linalg.norm(z_in_image)
    tilt = np.degrees(np.arccos(np.clip(ups @ z_in_image, -1, 1)))
    assert np.median(tilt) < 10 and np.mean(tilt < 30) > 0.8 and tilt.max() > 60


def test_the_frame_is_centred_on_the_curves_and_scaled_by_the_factor():
    pts = np.array([[0, 0, 0], [30.0, 0, 0], [30, 10, 5], [0, 10, 5]])
    d = np.array([0.3, -0.4, -0.87])
    d /= np.linalg.norm(d)
    cam = frame_curves(pts, d, np.array([0, 0, 1.0]), 2.0, 256)
    px = cam.project(pts)[0]
    lo, hi = px.min(axis=0), px.max(axis=0)
    assert np.allclose((lo + hi) / 2, 128.0, atol=1e-6)
    assert (hi - lo).max() == pytest.approx(128.0)


def _walled_plate() -> cq.Solid:
    """A 60 x 60 x 10 plate with a 60 x 6 x 40 wall along its -y edge."""
    plate = cq.Solid.makeBox(60, 60, 10, cq.Vector(-30, -30, -10))
    wall = cq.Solid.makeBox(60, 6, 40, cq.Vector(-30, -30, 0))
    return plate.fuse(wall).clean().Solids()[0]


@pytest.mark.parametrize("toward_the_wall, informative", [(False, True), (True, False)])
def test_a_view_whose_base_curve_is_hidden_is_rejected(renderer, toward_the_wall, informative):
    """A prism sketched on the plate right behind the wall: from the open side its base is
    in full view; looking over the wall (70 degrees off the normal), the wall hides it."""
    solid = _walled_plate()
    square = ((-8.0, -20.0, 0.0), (8.0, -20.0, 0.0), (8.0, -6.0, 0.0), (-8.0, -6.0, 0.0))
    op = AddSubPrism(FaceRef((0.0, 10.0, 0.0), (0.0, 0.0, 1.0)), square, 10.0, Mode.ADD)
    tilt = np.radians(70.0)
    d = np.array([0.0, np.sin(tilt) * (1 if toward_the_wall else -1), -np.cos(tilt)])
    curves = operation_curves(solid, op, d)
    camera = frame_curves(np.concatenate([c.points for c in curves]), d, np.array([0, 0, 1.0]), 2.0)
    maps = renderer.render(solid, camera)
    assert is_informative(curves, camera, maps) is informative
    seen = relevant_visibility(curves, camera, maps)
    assert seen > 0.95 if informative else seen < 0.5


def test_a_view_where_the_base_face_covers_a_few_pixels_is_rejected(renderer):
    """The 60 x 6 mm top of the wall, framed at 2 and at 10 times its size."""
    solid = _walled_plate()
    top = next(i for i, f in enumerate(solid.Faces()) if f.Center().z > 39.9)
    corners = np.array([[-30.0, -30, 40], [30, -24, 40]])
    d = np.array([0.0, 0.5, -np.sqrt(0.75)])
    for factor, shown in ((2.0, True), (10.0, False)):
        camera = frame_curves(corners, d, np.array([0, 0, 1.0]), factor)
        maps = renderer.render(solid, camera)
        assert np.count_nonzero(maps.face_id == top) > 0
        assert shows_base_face(maps, top) is shown
