# SPDX-License-Identifier: LGPL-2.1-or-later
"""Occlusion tests against the rendered depth: hidden, seen, edges, outside the image."""

import numpy as np

from Sketch2CADWorkbench.render.visibility import visible, visible_fraction


def box_edges(size, n=30):
    """Points along all twelve edges of the box centred on the origin."""
    h = size / 2
    t = np.linspace(-1, 1, n)
    pts = []
    for axis in range(3):
        a, b = [k for k in range(3) if k != axis]
        for sa in (-1, 1):
            for sb in (-1, 1):
                p = np.zeros((n, 3))
                p[:, axis] = t * h[axis]
                p[:, a], p[:, b] = sa * h[a], sb * h[b]
                pts.append(p)
    return np.concatenate(pts)


def test_a_point_behind_the_box_is_hidden_and_one_on_the_top_face_is_seen(
    renderer, box, box_size, oblique
):
    m = renderer.render(box, oblique)
    tol = 1e-3 * np.linalg.norm(box_size)
    top, under = [0.0, 0.0, box_size[2] / 2], [0.0, 0.0, -box_size[2] / 2 - 1.0]
    assert visible(np.array([top, under]), oblique, m, tol).tolist() == [True, False]


def test_edges_between_visible_faces_and_on_the_outline_are_seen(renderer, box, box_size, oblique):
    m = renderer.render(box, oblique)
    pts = box_edges(box_size)
    # An edge shows when one of its two faces turns to the camera.
    f = oblique.basis()[2]
    normal_sides = np.sign(pts / (box_size / 2)) * (np.abs(pts) >= box_size / 2 - 1e-9)
    faces_visible = (normal_sides * -f).max(axis=1) > 0
    seen = visible(pts, oblique, m, tol=1e-3 * np.linalg.norm(box_size))
    # Hidden edges end at outline corners, and points within a pixel or so of the
    # outline count as seen: compare away from the corners.
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    px, _ = oblique.project(pts)
    cx, _ = oblique.project(corners * box_size / 2)
    away = np.linalg.norm(px[:, None] - cx[None], axis=2).min(axis=1) > 2.5
    assert np.array_equal(seen[away], faces_visible[away])
    assert faces_visible[away].any() and not faces_visible[away].all()
    assert seen[faces_visible].all()


def test_points_outside_the_image_are_not_visible(renderer, box, oblique):
    m = renderer.render(box, oblique)
    far_right = oblique.unproject([[oblique.width + 5.0, oblique.height / 2]])
    assert not visible(far_right, oblique, m, 1.0)[0]
    assert visible_fraction(np.zeros((0, 3)), oblique, m, 1.0) == 0.0


def test_visible_fraction_is_the_share_of_visible_points(renderer, box, box_size, oblique):
    m = renderer.render(box, oblique)
    pts = np.array([[0.0, 0.0, box_size[2] / 2]] * 3 + [[0.0, 0.0, -box_size[2] / 2 - 1]])
    assert visible_fraction(pts, oblique, m, 0.01) == 0.75
