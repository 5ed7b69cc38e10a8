# SPDX-License-Identifier: LGPL-2.1-or-later
"""Cameras: the context frustum twice the sketch's box, and framing a shape."""

import numpy as np
import pytest

from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.frustum import context_camera, fit_camera
from Sketch2CADWorkbench.render.mesh import tessellate


def test_context_camera_is_twice_the_sketch_box_centred_on_it():
    view = OrthoCamera((3, -2, 1), (0.3, 1.0, -0.5), (0, 0, 1), 50.0, 400, 300)
    pts = np.array([[100.0, 100.0], [180.0, 140.0], [120.0, 110.0]])
    ctx = context_camera(view, pts)
    assert (ctx.width, ctx.height) == (256, 256)
    assert ctx.direction == view.direction and ctx.up == view.up
    # The larger side of the sketch box (80 px) spans half the context image.
    back, _ = ctx.project(view.unproject(pts))
    span = back.max(axis=0) - back.min(axis=0)
    assert span.max() == pytest.approx(256 / 2)
    assert (back.max(axis=0) + back.min(axis=0)) / 2 == pytest.approx([128, 128])
    assert ctx.scale == pytest.approx(80 * view.pixel_size)  # half of twice the box


def test_context_camera_of_a_dot_still_has_a_finite_window():
    view = OrthoCamera((0, 0, 0), (0, 0, -1), (0, 1, 0), 50.0, 400, 400)
    ctx = context_camera(view, np.array([[10.0, 10.0]]), size=128)
    assert ctx.scale > 0 and (ctx.width, ctx.height) == (128, 128)


@pytest.mark.parametrize("direction", [(1, 1, -1), (0, 0, -1), (-0.3, 1, 0.2)])
def test_fit_camera_frames_the_whole_box_with_the_margin(renderer, box, direction):
    margin = 1.1
    cam = fit_camera(
        box, direction, (0, 1, 0) if direction == (0, 0, -1) else (0, 0, 1), margin, (200, 150)
    )
    fg = renderer.render(box, cam).face_id >= 0
    assert not fg[0].any() and not fg[-1].any() and not fg[:, 0].any() and not fg[:, -1].any()
    rows, cols = np.flatnonzero(fg.any(axis=1)), np.flatnonzero(fg.any(axis=0))
    # The box fills 1 / margin of the image along its limiting dimension.
    filled = max((rows[-1] - rows[0] + 1) / 150, (cols[-1] - cols[0] + 1) / 200)
    assert filled == pytest.approx(1 / margin, abs=2 / 150)
    centre = np.array([(cols[0] + cols[-1] + 1) / 2, (rows[0] + rows[-1] + 1) / 2])
    assert centre == pytest.approx([100, 75], abs=1.0)


def test_fit_camera_accepts_a_mesh_or_a_bounding_box(box, box_size):
    d, up = (1, -1, -0.8), (0, 0, 1)
    from_mesh = fit_camera(tessellate(box), d, up, 1.2, 256)
    from_bbox = fit_camera(np.array([-box_size / 2, box_size / 2]), d, up, 1.2, 256)
    assert from_mesh.scale == pytest.approx(from_bbox.scale)
    assert np.allclose(from_mesh.center, from_bbox.center)


def test_the_image_of_a_vector_is_the_same_pixel_shift_wherever_it_starts():
    d = np.array([0.3, -1.0, -0.6])
    cam = OrthoCamera(
        (5.0, 2.0, 1.0), tuple(d / np.linalg.norm(d)), (0.0, 0.0, 1.0), 40.0, 320, 200
    )
    v = np.array([3.0, -1.0, 2.0])
    for p in (np.zeros(3), np.array([12.0, -7.0, 30.0])):
        shift = cam.project(np.stack([p, p + v]))[0]
        assert cam.image_of(v) == pytest.approx(shift[1] - shift[0], abs=1e-9)
