# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sample's strokes cut and joined as interpret reads them, each piece labelled with the
role of the curve it draws."""

import numpy as np

from Sketch2CADWorkbench.render.strokes import rasterize
from training.pieces import sketch_pieces

SIZE = 128


def _maps(curves, labels):
    """C~ painted per curve and M~, as the data generator paints a person's strokes."""
    curve = rasterize(curves, SIZE, SIZE, [float(v) for v in labels])
    mask = rasterize(curves, SIZE, SIZE) > 0
    return curve, mask


def _line(a, b, n=40):
    return np.linspace(a, b, n)


def test_an_outline_drawn_in_one_stroke_is_cut_into_its_curves_with_their_roles():
    # an L in one stroke: a base edge (role 0) then a side edge (role 1), and a separate
    # edge (role 2)
    base, side = _line((20, 100), (90, 100)), _line((90, 100), (90, 40))
    other = _line((20, 30), (60, 30))
    curve, mask = _maps([base, side, other], [0, 1, 2])
    pieces, roles = sketch_pieces([np.vstack([base, side[1:]]), other], curve, mask)
    assert len(pieces) == 3
    by_start = sorted(zip(pieces, roles, strict=True), key=lambda pr: tuple(pr[0].mean(0)))
    assert sorted(roles) == [0, 1, 2]
    for piece, role in by_start:
        mid = piece.mean(0)
        want = 2 if mid[1] < 35 else (0 if mid[1] > 95 else 1)
        assert role == want, (mid, role)


def test_an_edge_drawn_in_two_strokes_is_one_piece_with_its_role():
    edge = _line((10, 60), (110, 60), 80)
    curve, mask = _maps([edge], [1])
    pieces, roles = sketch_pieces([edge[:42], edge[38:]], curve, mask)
    assert len(pieces) == 1 and roles == [1]
