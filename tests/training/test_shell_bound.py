# SPDX-License-Identifier: LGPL-2.1-or-later
"""The shell bound: what the rim strokes' tips tell of t, and how sure the best reading is."""

from types import SimpleNamespace

import pytest

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box, FaceRef, Protocol, Shell
from Sketch2CADWorkbench.render.frustum import fit_camera
from Sketch2CADWorkbench.sketch.curves import operation_curves
from training.shell_bound import shell_bound

TOP = FaceRef((0.0, 0.0, 10.0), (0.0, 0.0, 1.0))


def _sample(t_drawn: float, direction, t_true: float = 4.0, noise_level: int = 1):
    """A shell of a box open at its top, t_true thick, whose rim a steady hand drew as
    for t_drawn."""
    base = Box((40.0, 30.0, 20.0))
    box = make_box(base)
    camera = fit_camera(box, direction)
    curves = operation_curves(box, Shell(TOP, t_drawn), camera.direction)
    return SimpleNamespace(
        context=Protocol(base),
        operation=Shell(TOP, t_true),
        camera=camera,
        noise_level=noise_level,
        strokes=[camera.project(c.points)[0] for c in curves],
        stroke_parts=[int(c.label) for c in curves],
    )


def test_the_oracle_reads_t_from_the_tips_drawn_at_the_rims_corners():
    exact = shell_bound(_sample(4.0, (1.0, 0.6, -1.0)))
    assert exact.t_ml == pytest.approx(4.0, abs=1e-4) and exact.ml_recovered
    assert exact.tips == 8  # two per corner of the rectangular rim
    thick = shell_bound(_sample(5.0, (1.0, 0.6, -1.0)))  # the hand drew the rim 1 mm in
    assert thick.t_ml == pytest.approx(5.0, abs=1e-4) and not thick.ml_recovered
    assert thick.sd == pytest.approx(exact.sd, rel=1e-3)  # the same view, as sure
    assert exact.fit_recovered and not thick.fit_recovered  # the project's fitting, told f


def test_a_noisier_hand_or_a_grazing_view_leaves_the_best_reading_less_sure():
    steady = shell_bound(_sample(4.0, (1.0, 0.6, -1.0)))
    shaky = shell_bound(_sample(4.0, (1.0, 0.6, -1.0), noise_level=3))
    grazing = shell_bound(_sample(4.0, (1.0, 0.6, -0.2)))  # the top seen nearly edge-on
    assert shaky.sd > 2 * steady.sd and grazing.sd > steady.sd
    assert 0.0 < shaky.p_best < steady.p_best <= 1.0
