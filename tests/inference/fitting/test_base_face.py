# SPDX-License-Identifier: LGPL-2.1-or-later
"""The base face is the planar face the face map counts most, and a sketch beside the model
is a fit error."""

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, Mode, Sweep
from Sketch2CADWorkbench.inference.fitting.base_face import (
    face_most_under,
    face_under_stroke,
    face_under_strokes,
    rank_base_faces,
    select_base_face,
)
from Sketch2CADWorkbench.inference.fitting.common import FitError


def test_base_face_is_counted_and_an_unsure_face_map_still_decides():
    box = make_box(Box((40, 30, 20)))
    ids = np.zeros((64, 64), np.int32)
    ids[:, 32:] = 5
    ids[:4] = -1
    sure = np.where(ids == 5, 0.9, 0.1)
    assert select_base_face(sure, ids, box).isSame(box.Faces()[5])
    unsure = np.where(ids == 5, 0.4, 0.2)  # nothing passes 0.5: the higher mean wins
    assert select_base_face(unsure, ids, box).isSame(box.Faces()[5])


def test_a_sketch_beside_the_model_is_a_fit_error_not_a_crash():
    box = make_box(Box((40, 30, 20)))
    background = np.full((64, 64), -1, np.int32)
    with pytest.raises(FitError, match="not in view"):
        select_base_face(np.full((64, 64), 0.9), background, box)


def post_in_view():
    """A post on a box, its side filling most of a 64 x 64 view and its top disk a band
    under it: (solid, face ids, side's index, disk's index)."""
    box = make_box(Box((40, 30, 20)))
    top = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))
    post = apply_operation(
        box, Sweep(top, (0.0, 0.0, 10.0), 5.0, 5.0, 10.0, ((5.0, 10 / 3), (5.0, 20 / 3)), Mode.ADD)
    )
    faces = post.Faces()
    side = next(i for i, f in enumerate(faces) if f.geomType() == "CYLINDER")
    disk = next(
        i
        for i, f in enumerate(faces)
        if f.geomType() == "PLANE" and abs(f.Center().z - 20.0) < 1e-6
    )
    ids = np.full((64, 64), -1, np.int32)
    ids[:40] = side
    ids[40:50] = disk
    return post, ids, side, disk


def test_base_face_is_planar_even_when_a_curved_face_gets_more_votes():
    post, ids, _side, disk = post_in_view()
    got = select_base_face(np.where(ids >= 0, 0.9, 0.0), ids, post)
    assert got.isSame(post.Faces()[disk])


def test_for_prisms_and_sweeps_a_curved_face_counts_by_its_votes_only():
    post, ids, side, disk = post_in_view()
    voted = rank_base_faces(np.where(ids >= 0, 0.9, 0.0), ids, post, curved=True)
    assert voted[0] == side and disk in voted
    # an unsure F (no pixel over 0.5) never puts the large curved face in
    unsure = rank_base_faces(np.where(ids == side, 0.45, 0.3), ids, post, curved=True)
    assert side not in unsure and unsure[0] == disk


def test_an_outline_with_one_side_drawn_off_its_face_still_lies_on_the_face():
    # a 64 x 64 view: face 2 in the middle, face 7 a band at the right, the air around
    ids = np.full((64, 64), -1, np.int32)
    ids[8:56, 8:48] = 2
    ids[8:56, 48:60] = 7
    # a rectangle's four sides (x, y), the right one drawn past face 2 onto face 7
    top, right = np.linspace((12, 12), (40, 12), 30), np.linspace((52, 12), (52, 44), 30)
    bottom, left = np.linspace((40, 44), (12, 44), 30), np.linspace((12, 44), (12, 12), 30)
    sides = [top, right, bottom, left]
    assert face_under_stroke(right, ids) == 7
    assert face_under_strokes(sides, ids) == 2
    # drawn in the air for the most part: on no face
    assert face_under_strokes([s + [0.0, 30.0] for s in sides], ids) is None


def test_a_rim_mostly_in_the_air_is_drawn_on_the_face_most_of_the_rest_lies_on():
    # face 2 a thin band, face 7 beside it, the air around: a hand's rim on the band's
    # face runs past it onto face 7 and into the air for the most part
    ids = np.full((64, 64), -1, np.int32)
    ids[20:30, 8:56] = 2
    ids[30:34, 8:56] = 7
    rim = [np.linspace((10, 22), (54, 22), 30), np.linspace((10, 33), (54, 33), 30)]
    rim += [np.linspace((10, 2), (10, 60), 30), np.linspace((54, 2), (54, 60), 30)]
    assert face_under_strokes(rim, ids) is None
    assert face_most_under(rim, ids) == 2
    assert face_most_under([s + [0.0, 40.0] for s in rim], np.full((64, 64), -1)) is None
