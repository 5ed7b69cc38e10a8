# SPDX-License-Identifier: LGPL-2.1-or-later
"""The head's choice painted into the F and C maps."""

import numpy as np
import torch
from head_fixtures import SIZE, scene

from datagen.strokes import stroke_maps
from Sketch2CADWorkbench.inference.head.paint import paint_curve, paint_face


def test_painted_roles_reproduce_the_generators_curve_label():
    _, strokes = scene()
    labels = [2, 0, 1]
    truth = stroke_maps(strokes, labels, SIZE, SIZE).curve_label
    assert np.array_equal(paint_curve(strokes, labels, SIZE), truth)


def test_painted_face_map_shows_the_chosen_face_and_orders_the_rest():
    face_id, _ = scene()
    f = paint_face(torch.tensor([0.3, 0.7]), torch.tensor([3, 7]), face_id, 1)
    assert np.array_equal(f > 0.5, face_id == 7)
    assert 0 < f[face_id == 3].max() <= 0.5 and f[face_id < 0].max() == 0
    f = paint_face(torch.tensor([0.3, 0.7]), torch.tensor([3, 7]), face_id, 0)
    assert np.array_equal(f > 0.5, face_id == 3)  # chosen with the roles, not the likeliest
