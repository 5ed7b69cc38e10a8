# SPDX-License-Identifier: LGPL-2.1-or-later
"""Bevel fitting finds the corner, its crease and the profile the strokes were drawn from."""
import numpy as np
import pytest
from fit_sketches import FRONT_Y, TOP_Z, curve_stroke, face_towards

from Sketch2CADWorkbench.brep.geometry import bezier
from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.inference.fitting.bevel import fit_bevel
from Sketch2CADWorkbench.inference.fitting.common import FitError


def bevel_profile():
    """A rounded profile at the front face's top-left corner (-20, -15, 10)."""
    return np.array([[-14.0, FRONT_Y, TOP_Z], [-17.5, FRONT_Y, TOP_Z], [-20, FRONT_Y, 7.5],
                     [-20, FRONT_Y, 4.0]])


def test_bevel_fit_finds_the_corner_its_crease_and_the_profile(box, camera):
    ctrl = bevel_profile()
    face = face_towards(box, (0, -1, 0))
    op = fit_bevel(box, face, camera, curve_stroke(camera, bezier(ctrl, np.linspace(0, 1, 40))))
    assert op.corner == pytest.approx((-20, FRONT_Y, TOP_Z))
    assert op.opposite == pytest.approx((-20, -FRONT_Y, TOP_Z))
    assert np.array(op.profile) == pytest.approx(ctrl, abs=0.3)
    assert apply_operation(box, op).isValid()


def test_bevel_stroke_drawn_backwards_gives_the_same_corner(box, camera):
    ctrl = bevel_profile()[::-1]
    op = fit_bevel(box, face_towards(box, (0, -1, 0)), camera,
                   curve_stroke(camera, bezier(ctrl, np.linspace(0, 1, 40))))
    assert op.corner == pytest.approx((-20, FRONT_Y, TOP_Z))


def test_bevel_profile_inside_the_face_is_refused(box, camera):
    inner = np.array([[-5, FRONT_Y, 0], [-2, FRONT_Y, 3], [2, FRONT_Y, 3], [5, FRONT_Y, 0]])
    with pytest.raises(FitError, match="from one edge of the face to another"):
        fit_bevel(box, face_towards(box, (0, -1, 0)), camera,
                  curve_stroke(camera, bezier(inner, np.linspace(0, 1, 30))))
