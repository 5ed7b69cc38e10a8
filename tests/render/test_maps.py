# SPDX-License-Identifier: LGPL-2.1-or-later
"""Context maps are exact where a caller checks them: IDs, depths, normals, pixels."""
import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.frustum import context_camera, fit_camera
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.strokes import rasterize
from Sketch2CADWorkbench.render.visibility import visible

SIZE = (40.0, 30.0, 20.0)


@pytest.fixture(scope="module")
def renderer():
    return MapRenderer()


@pytest.fixture(scope="module")
def box():
    return make_box(Box(SIZE))


def oblique():
    d = np.array([0.7, 1.0, -1.1])
    return OrthoCamera((0.0, 0.0, 0.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 35.0)


def face_with_normal(solid, n):
    return next(i for i, f in enumerate(solid.Faces()) if np.dot(f.normalAt().toTuple(), n) > 0.999)


def test_top_down_view_sees_only_the_top_face_flat(renderer, box):
    cam = OrthoCamera((0, 0, 0), (0, 0, -1), (0, 1, 0), 20.0, 128, 128)
    m = renderer.render(box, cam)
    fg = m.face_id >= 0
    top = face_with_normal(box, (0, 0, 1))
    assert set(np.unique(m.face_id[fg])) == {top}
    # The box spans 40 x 30 mm of a 40 x 40 mm view: 128 x 96 pixels.
    assert fg.sum() == 128 * 96
    assert np.allclose(m.depth[fg], 1.0) and np.all(m.depth[~fg] == 0)
    assert np.allclose(m.view_depth[fg], -SIZE[2] / 2, atol=1e-3)
    assert np.allclose(m.normal[:, fg].T, [1.0, 1.0, 2.0], atol=1 / 127)  # facing the viewer
    assert np.all(m.normal[:, ~fg] == 0)


def test_oblique_view_sees_three_faces_with_their_normals(renderer, box):
    cam = oblique()
    m = renderer.render(box, cam)
    r, u, f = cam.basis()
    seen = set(np.unique(m.face_id)) - {-1}
    assert len(seen) == 3
    for i in seen:
        n = np.array(box.Faces()[i].normalAt().toTuple())
        assert n @ f < 0  # only faces turned to the camera
        expected = np.array([n @ r, n @ u, -(n @ f)]) + 1
        assert np.allclose(m.normal[:, m.face_id == i].mean(axis=1), expected, atol=0.01)


def test_known_point_lands_on_its_face_at_its_depth(renderer, box):
    cam = oblique()
    m = renderer.render(box, cam)
    point = np.array([[5.0, -3.0, SIZE[2] / 2]])  # on the top face
    px, depth = cam.project(point)
    i, j = np.floor(px[0]).astype(int)
    assert m.face_id[j, i] == face_with_normal(box, (0, 0, 1))
    assert m.view_depth[j, i] == pytest.approx(depth[0], abs=2 * cam.pixel_size)


def test_box_corner_projects_onto_the_meeting_of_three_faces(renderer, box):
    cam = oblique()
    m = renderer.render(box, cam)
    px, _ = cam.project([[-SIZE[0] / 2, -SIZE[1] / 2, SIZE[2] / 2]])
    i, j = np.floor(px[0]).astype(int)
    around = set(np.unique(m.face_id[j - 1:j + 2, i - 1:i + 2]))
    assert len(around - {-1}) == 3


def test_depth_map_is_normalised_farthest_zero_closest_one(renderer, box):
    m = renderer.render(box, oblique())
    fg = m.face_id >= 0
    assert m.depth[fg].min() == pytest.approx(0.0) and m.depth[fg].max() == pytest.approx(1.0)
    closest = np.unravel_index(np.argmax(np.where(fg, m.depth, -1)), m.depth.shape)
    assert m.view_depth[closest] == pytest.approx(m.view_depth[fg].min())


def test_point_behind_the_box_is_hidden_and_a_top_point_is_seen(renderer, box):
    cam = oblique()
    m = renderer.render(box, cam)
    pts = np.array([[0.0, 0.0, SIZE[2] / 2], [0.0, 0.0, -SIZE[2] / 2 - 1]])
    assert visible(pts, cam, m, tol=0.05).tolist() == [True, False]


def test_rasterize_draws_the_segment_pixels_with_their_values():
    img = rasterize([np.array([[2.5, 3.5], [9.5, 3.5]]), np.array([[5.5, 0.5], [5.5, 7.5]])],
                    12, 8, values=[1.0, 2.0])
    assert np.all(img[3, 2:10] == np.where(np.arange(2, 10) == 5, 2.0, 1.0))
    assert np.all(img[0:8, 5] == 2.0)
    assert (img > 0).sum() == 8 + 8 - 1


def test_context_camera_is_twice_the_sketch_box_centred_on_it():
    view = OrthoCamera((0, 0, 0), (0, 0, -1), (0, 1, 0), 50.0, 400, 400)
    pts = np.array([[100.0, 100.0], [180.0, 140.0]])
    ctx = context_camera(view, pts)
    assert ctx.scale * 2 == pytest.approx(2 * 80 * view.pixel_size)
    back = ctx.project(view.unproject(pts.mean(axis=0)[None]))[0][0]
    assert back == pytest.approx([128, 128])
    assert (ctx.width, ctx.height) == (256, 256)


def test_fit_camera_frames_the_whole_box(renderer, box):
    cam = fit_camera((-20, -15, -10), (20, 15, 10), (1, 1, -1), (0, 0, 1), margin=1.05)
    m = renderer.render(box, cam)
    fg = m.face_id >= 0
    assert not fg[0].any() and not fg[-1].any() and not fg[:, 0].any() and not fg[:, -1].any()
