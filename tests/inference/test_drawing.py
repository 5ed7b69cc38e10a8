# SPDX-License-Identifier: LGPL-2.1-or-later
"""A prism's drawing as a corner graph: the labellings its strokes allow."""

import numpy as np
import pytest
from drawing_fixtures import SIZE, prism_drawing

from Sketch2CADWorkbench.inference.drawing import prism_labellings


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_a_noisy_prism_drawing_allows_its_own_labelling(n):
    for seed in range(5):
        strokes, truth = prism_drawing(n, seed)
        labellings = prism_labellings(strokes, SIZE)
        assert any(list(lab) == truth for lab in labellings), seed
        assert all(sorted(lab) == sorted(truth) for lab in labellings)
    # drawn exactly, a triangle's, pentagon's or hexagon's graph splits one way into two
    # outlines and the profiles, a quadrilateral's (a cube's graph) three ways; each
    # outline as start or as end
    assert len(prism_labellings(prism_drawing(n, 0, noise=0.0)[0], SIZE)) == (6 if n == 4 else 2)


def test_strokes_that_draw_no_prism_allow_no_labelling():
    rng = np.random.default_rng(0)
    scribble = [rng.uniform(0, SIZE, (2, 2)) for _ in range(9)]
    assert prism_labellings(scribble, SIZE) == []
    strokes, _ = prism_drawing(4, 0)
    assert prism_labellings(strokes[:-1], SIZE) == []  # a side edge left out
