# SPDX-License-Identifier: LGPL-2.1-or-later
"""Context maps are exact where callers rely on them: pixels, face IDs, depths, normals."""

import os
import subprocess
import sys

import numpy as np
import pytest

from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.mesh import FaceMesh, tessellate


def corners(size):
    lx, ly, lz = size / 2
    return np.array([[x, y, z] for x in (-lx, lx) for y in (-ly, ly) for z in (-lz, lz)])


def test_top_down_view_shows_the_top_face_on_exactly_the_pixels_it_covers(
    renderer, box, box_size, face_of
):
    # Off-centre and non-square, so the box edges fall between pixel centres.
    cam = OrthoCamera((1.3, -0.7, 0.0), (0, 0, -1), (0, 1, 0), 23.0, 128, 100)
    m = renderer.render(box, cam)
    px, _ = cam.project(corners(box_size))
    x0, x1 = px[:, 0].min(), px[:, 0].max()
    y0, y1 = px[:, 1].min(), px[:, 1].max()
    xc, yc = np.meshgrid(np.arange(128) + 0.5, np.arange(100) + 0.5)
    inside = (xc > x0) & (xc < x1) & (yc > y0) & (yc < y1)
    clear = (np.minimum(np.abs(xc - x0), np.abs(xc - x1)) > 1e-3) & (
        np.minimum(np.abs(yc - y0), np.abs(yc - y1)) > 1e-3
    )
    fg = m.face_id >= 0
    assert np.array_equal(fg[clear], inside[clear])
    assert set(np.unique(m.face_id[fg])) == {face_of(box, (0, 0, 1))}
    # The top face is at z = lz / 2; the view looks down -z from the plane z = 0.
    assert np.allclose(m.view_depth[fg], -box_size[2] / 2, atol=1e-4)
    assert np.all(np.isinf(m.view_depth[~fg]))
    assert np.all(m.depth[fg] == 1.0) and np.all(m.depth[~fg] == 0.0)
    # Camera space: x right, y up, z to the viewer; the top faces the viewer: (0, 0, 1) + 1.
    assert np.allclose(m.normal[:, fg].T, [1.0, 1.0, 2.0], atol=1e-5)
    assert np.all(m.normal[:, ~fg] == 0.0)
    assert m.depth.dtype == m.normal.dtype == m.view_depth.dtype == np.float32
    assert m.face_id.dtype == np.int32
    assert m.normal.shape == (3, 100, 128) and m.face_id.shape == (100, 128)


def test_oblique_view_shows_the_three_faces_turned_to_the_camera_with_their_normals(
    renderer, box, oblique
):
    m = renderer.render(box, oblique)
    r, u, f = oblique.basis()
    facing = {i for i, face in enumerate(box.Faces()) if np.dot(face.normalAt().toTuple(), f) < 0}
    assert len(facing) == 3
    assert set(np.unique(m.face_id)) - {-1} == facing
    for i in facing:
        n = np.array(box.Faces()[i].normalAt().toTuple())
        expected = np.array([n @ r, n @ u, -(n @ f)]) + 1.0
        assert expected[2] > 1.0  # facing the viewer: camera-space z > 0
        assert np.allclose(m.normal[:, m.face_id == i].T, expected, atol=1e-5)


def test_a_point_on_a_visible_face_has_that_face_and_its_depth_at_its_pixel(
    renderer, box, box_size, oblique
):
    m = renderer.render(box, oblique)
    margin = 2 * oblique.pixel_size  # keep away from edges: a pixel is 0.27 mm here
    rng = np.random.default_rng(1)
    checked = 0
    for i, face in enumerate(box.Faces()):
        n = np.array(face.normalAt().toTuple())
        if n @ oblique.basis()[2] >= 0:
            continue
        axis = int(np.argmax(np.abs(n)))
        half = box_size / 2
        pts = rng.uniform(-half + margin, half - margin, (40, 3))
        pts[:, axis] = np.sign(n[axis]) * half[axis]
        px, depth = oblique.project(pts)
        col, row = np.floor(px).astype(int).T
        assert np.all(m.face_id[row, col] == i)
        # The map holds the depth at the pixel centre: the point's depth plus the face's
        # depth slope over the offset from the point to that centre.
        centre_pts = oblique.back_project_to_plane(np.stack([col, row], 1) + 0.5, pts[0], n)
        _, centre_depth = oblique.project(centre_pts)
        assert np.allclose(m.view_depth[row, col], centre_depth, atol=1e-4)
        assert np.allclose(centre_depth, depth, atol=oblique.pixel_size * 3)
        checked += len(pts)
    assert checked == 120


def test_box_edges_in_the_face_id_map_lie_within_a_pixel_of_their_projection(
    renderer, box, box_size, oblique, face_of
):
    m = renderer.render(box, oblique)
    lx, ly, lz = box_size / 2
    top, right, front = (face_of(box, n) for n in ((0, 0, 1), (1, 0, 0), (0, -1, 0)))
    corner = np.array([[lx, -ly, lz]])  # where the three visible faces meet
    ((cx, cy),) = oblique.project(corner)[0]
    i, j = int(cx), int(cy)
    assert set(np.unique(m.face_id[j - 1 : j + 2, i - 1 : i + 2])) == {top, right, front}
    # Along the top / +x crease, the pixels one pixel to either side see the two faces.
    t = np.linspace(-ly + 1, ly - 1, 25)
    edge = np.stack([np.full_like(t, lx), t, np.full_like(t, lz)], 1)
    p, _ = oblique.project(edge)
    d = p[-1] - p[0]
    side = np.array([-d[1], d[0]]) / np.linalg.norm(d)
    inward, _ = oblique.project([[0.0, 0.0, lz]])  # a point inside the top face
    if (inward[0] - p[0]) @ side < 0:
        side = -side
    for sign, face in ((1.0, top), (-1.0, right)):
        q = np.floor(p + sign * side).astype(int)
        assert np.all(m.face_id[q[:, 1], q[:, 0]] == face)


def test_depth_is_view_depth_mapped_linearly_farthest_zero_closest_one(
    renderer, box, box_size, oblique
):
    m = renderer.render(box, oblique)
    fg = m.face_id >= 0
    vd = m.view_depth[fg].astype(np.float64)
    expected = (vd.max() - vd) / (vd.max() - vd.min())
    assert np.allclose(m.depth[fg], expected, atol=1e-5)
    assert m.depth[fg].min() == 0.0 and m.depth[fg].max() == 1.0
    # The nearest visible point of the box is the corner facing the camera.
    _, corner_depth = oblique.project([box_size * [0.5, -0.5, 0.5]])
    assert vd.min() == pytest.approx(corner_depth[0], abs=3 * oblique.pixel_size)


def test_curved_faces_get_smooth_normals(renderer, cylinder):
    # Looking along +y at the vertical cylinder: at image x the visible surface point
    # has world normal (x / R, -sqrt(1 - (x / R)^2), 0); in camera space
    # (x / R, 0, sqrt(1 - (x / R)^2)).
    radius = 10.0
    cam = OrthoCamera((0.0, 0.0, 10.0), (0, 1, 0), (0, 0, 1), 12.0, 256, 256)
    m = renderer.render(cylinder, cam)
    cols = np.arange(256) + 0.5
    x = (cols - 128) * cam.pixel_size
    rows = slice(int(128 - 8 / cam.pixel_size), int(128 + 8 / cam.pixel_size))
    keep = np.abs(x) < 0.95 * radius  # away from the faceted silhouette
    s = x[keep] / radius
    expected = np.stack([s, np.zeros_like(s), np.sqrt(1 - s**2)]) + 1.0
    got = m.normal[:, rows][:, :, keep]
    # Flat triangles would be off by half a segment angle (about 0.1 here).
    assert np.abs(got - expected[:, None, :]).max() < 0.02


def test_one_renderer_serves_many_meshes_and_sizes(renderer, box, cylinder, oblique):
    box_mesh, cyl_mesh = tessellate(box), tessellate(cylinder)
    first = renderer.render(box_mesh, oblique)
    small = renderer.render(cyl_mesh, oblique.with_size(96, 64))
    again = renderer.render(box_mesh, oblique)
    assert np.array_equal(first.face_id, again.face_id)
    assert np.array_equal(first.view_depth, again.view_depth)
    fresh = MapRenderer()
    try:
        alone = fresh.render(cyl_mesh, oblique.with_size(96, 64))
    finally:
        fresh.close()
    assert np.array_equal(small.face_id, alone.face_id)
    assert np.allclose(small.normal, alone.normal, atol=1e-6)


def test_a_solid_and_its_mesh_render_the_same_faces(renderer, box, oblique):
    assert np.array_equal(
        renderer.render(box, oblique).face_id, renderer.render(tessellate(box), oblique).face_id
    )


def test_rendering_without_a_display_prints_nothing():
    code = (
        "from Sketch2CADWorkbench.brep.operators import make_box\n"
        "from Sketch2CADWorkbench.brep.protocol import Box\n"
        "from Sketch2CADWorkbench.render.camera import OrthoCamera\n"
        "from Sketch2CADWorkbench.render.maps import MapRenderer\n"
        "import numpy as np\n"
        "cam = OrthoCamera((0, 0, 0), (0, 0, -1), (0, 1, 0), 10.0, 32, 32)\n"
        "m = MapRenderer().render(make_box(Box((4.0, 4.0, 4.0))), cam)\n"
        "c = (np.arange(32) + 0.5 - 16) * cam.pixel_size\n"
        "k = (np.abs(c) < 2.0).sum()\n"
        "assert k > 0 and (m.face_id >= 0).sum() == k * k\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    run = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout == "" and run.stderr == ""


@pytest.mark.parametrize(
    "direction", [(-0.7, 1.0, -1.1), (0.3, 1.0, -1e-4)], ids=["oblique", "grazing-top"]
)
def test_every_pixel_holds_the_depth_of_its_face_plane_at_the_pixel_centre(
    renderer, box, direction
):
    d = np.array(direction) / np.linalg.norm(direction)
    cam = OrthoCamera((0.5, -0.25, 0.0), tuple(d), (0, 0, 1), 30.0, 160, 160)
    m = renderer.render(box, cam)
    rows, cols = np.nonzero(m.face_id >= 0)
    centres = np.stack([cols, rows], 1) + 0.5
    faces = box.Faces()
    for i in np.unique(m.face_id[rows, cols]):
        on = m.face_id[rows, cols] == i
        n = np.array(faces[i].normalAt().toTuple())
        hit = cam.back_project_to_plane(centres[on], faces[i].Center().toTuple(), n)
        _, expected = cam.project(hit)
        # Relative to the float32 map values; a grazing face is steep in depth.
        assert np.allclose(m.view_depth[rows[on], cols[on]], expected, rtol=1e-6, atol=1e-4)


def test_a_sliver_seen_almost_edge_on_keeps_exact_depths(renderer):
    # A needle 58 px long and 0.01 px wide at its base along the pixel-centre row
    # y = 10.5, far from the image centre, its depth rising 115 mm along its axis and
    # 30 mm across its base: a face seen nearly edge-on.
    cam = OrthoCamera((0.0, 0.0, 0.0), (0.2, 0.3, -1.0), (0, 1, 0), 10.0, 64, 240)
    px = np.array([[2.0, 10.5], [60.0, 10.505], [60.0, 10.495]])
    depth = np.array([0.0, 100.0, 130.0])
    normal = np.tile(-np.array(cam.basis()[2]), (3, 1))
    mesh = FaceMesh(
        cam.unproject(px, depth),
        np.array([[0, 1, 2]], np.int32),
        np.zeros(1, np.int32),
        normal[:1],
        normal,
    )
    m = renderer.render(mesh, cam)
    rows, cols = np.nonzero(m.face_id == 0)
    assert len(cols) >= 20 and np.all(rows == 10)
    assert np.allclose(m.view_depth[rows, cols], 115.0 * (cols + 0.5 - 2.0) / 58.0, atol=1e-3)
