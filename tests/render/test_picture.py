# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shaded pictures: white background, shaded body, dark edges, strokes, PNG, sheets."""

import cv2
import numpy as np

from Sketch2CADWorkbench.render.picture import contact_sheet, default_camera, shaded_picture


def test_a_shaded_picture_has_a_white_background_a_shaded_body_and_dark_edges(
    renderer, box, tmp_path
):
    path = tmp_path / "box.png"
    img = shaded_picture(box, size=(160, 120), path=path, renderer=renderer)
    assert img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert np.all(img[0, 0] == 255) and np.all(img[-1, -1] == 255)
    cam = default_camera(box, 160, 120)
    ((cx, cy),) = cam.project([[0.0, 0.0, 10.0]])[0:1][0]  # middle of the top face
    body = img[int(cy), int(cx)].astype(int)
    assert body.max() < 250 and body[2] > body[0]  # grey-blue, not white
    assert (img.max(axis=2) < 60).sum() > 100  # the B-rep edges are drawn dark
    assert np.array_equal(cv2.imread(str(path))[..., ::-1], img)


def test_strokes_are_drawn_over_the_picture_in_orange(renderer, box):
    stroke = np.array([[10.0, 10.0], [60.0, 10.0]])
    img = shaded_picture(box, size=(160, 120), strokes=[stroke], renderer=renderer)
    r, g, b = img[10, 35].astype(int)
    assert r > 200 and 100 < g < 180 and b < 60


def test_contact_sheet_lays_pictures_out_in_rows():
    tiles = [np.full((20, 30, 3), k * 40, np.uint8) for k in range(5)]
    sheet = contact_sheet(tiles, 2, [str(k) for k in range(5)], pad=4)
    rows, cap = 3, 22
    assert sheet.shape == (rows * (20 + 4 + cap) + 4, 2 * (30 + 4) + 4, 3)
    assert np.all(sheet[4:24, 4 + 34 : 4 + 34 + 30] == 40)  # tile 1: first row, second column
    assert np.all(sheet[4 + 2 * (20 + 4 + cap) :, 4:34][:20] == 160)  # tile 4: third row
