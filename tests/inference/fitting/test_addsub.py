# SPDX-License-Identifier: LGPL-2.1-or-later
"""Prism fitting recovers the addition or subtraction that produced the strokes, and refuses
strokes no prism on the face explains."""

import numpy as np
import pytest
from fit_sketches import QUAD, TOP_Z, face_towards, prism_sketch

from Sketch2CADWorkbench.brep.operators import apply_operation
from Sketch2CADWorkbench.brep.protocol import Mode
from Sketch2CADWorkbench.inference.fitting.addsub import fit_prism, prism_fit, prism_fits
from Sketch2CADWorkbench.inference.fitting.common import FitError
from Sketch2CADWorkbench.inference.fitting.verify import sketch_fit


def test_prism_fit_recovers_an_addition_exactly(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(6.0, abs=0.2)
    got = np.array(op.polygon)
    for v in QUAD:  # same vertex set, any starting vertex
        assert np.min(np.linalg.norm(got - v, axis=1)) < 0.2


def test_a_start_outline_drawn_off_is_corrected_by_the_far_outline_and_side_edges(box, camera):
    # the start outline drawn 4 px to the right, the other eight strokes where they belong:
    # the base polygon follows the majority, not the four strokes that sit on f
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    strokes = [s + (4.0, 0.0) if l == 0 else s for s, l in zip(strokes, labels, strict=False)]
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    got = np.array(op.polygon)
    err = max(np.min(np.linalg.norm(got - v, axis=1)) for v in QUAD)
    # from the start outline alone the corners would be 4 px off
    assert err < 0.5 * 4.0 * camera.pixel_size and op.d == pytest.approx(6.0, abs=0.3)


def test_a_prism_fit_is_fitted_prism_once_refined_and_its_start_outlines_before(box, camera):
    # as above: unrefined, the base polygon is the start outline's, 4 px off
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    strokes = [s + (4.0, 0.0) if l == 0 else s for s, l in zip(strokes, labels, strict=False)]
    fit = prism_fit(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert fit.refined() == fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    off = max(np.min(np.linalg.norm(np.array(fit.operation.polygon) - v, axis=1)) for v in QUAD)
    assert off > 0.75 * 4.0 * camera.pixel_size


def test_deep_cut_is_read_as_a_subtraction(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 14.0, -1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)
    assert op.mode is Mode.SUBTRACT and op.d == pytest.approx(14.0, abs=0.2)


def test_a_plate_wider_than_the_column_top_it_stands_on_is_an_addition_on_it(box, camera):
    # a 10 x 10 column on the box, then a 30 x 24 plate on the column's top: no sample of
    # either plate outline lies on that face, but the plate's region covers all of it
    from Sketch2CADWorkbench.brep.protocol import AddSubPrism, FaceRef

    column = AddSubPrism(
        FaceRef((0.0, 0.0, TOP_Z), (0.0, 0.0, 1.0)),
        ((-5, -5, TOP_Z), (5, -5, TOP_Z), (5, 5, TOP_Z), (-5, 5, TOP_Z)),
        8.0,
        Mode.ADD,
    )
    solid = apply_operation(box, column)
    z = TOP_Z + 8.0
    top = next(f for f in solid.Faces() if f.normalAt().z > 0.999 and f.Center().z > z - 1e-6)
    plate = np.array([[-15, -12, z], [15, -12, z], [15, 12, z], [-15, 12, z]])
    strokes, labels = prism_sketch(camera, plate, 5.0, +1)
    op = fit_prism(solid, top, camera, strokes, labels)
    assert op.mode is Mode.ADD and op.d == pytest.approx(5.0, abs=0.3)
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in plate) < 0.5


def test_user_choice_of_option_wins(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels, option=Mode.SUBTRACT)
    assert op.mode is Mode.SUBTRACT


def test_a_prism_with_fewer_side_edges_than_sides_needs_one_outline_drawn_whole(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    # two sides of each outline and two side edges: no outline gives the corners
    keep = [0, 1, 4, 5, 8, 9]
    with pytest.raises(FitError, match="at least 3 sides"):
        fit_prism(
            box,
            face_towards(box, (0, 0, 1)),
            camera,
            [strokes[k] for k in keep],
            [labels[k] for k in keep],
        )


@pytest.mark.parametrize("count", [7])
def test_prism_needs_at_most_six_profile_strokes(box, camera, count):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    profiles = [s for s, l in zip(strokes, labels, strict=False) if l == 1]
    strokes = [s for s, l in zip(strokes, labels, strict=False) if l != 1] + (profiles * 2)[:count]
    labels = [l for l in labels if l != 1] + [1] * count
    with pytest.raises(FitError, match=f"3 to 6 profile strokes.*{count} were recognised"):
        fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)


def test_outlines_off_the_face_are_refused(box, camera):
    far = QUAD + np.array([60.0, 0, 0])
    strokes, labels = prism_sketch(camera, far, 6.0, +1)
    with pytest.raises(FitError, match="neither the start nor the end outline"):
        fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)


def test_a_hole_drawn_with_its_rim_one_side_edge_and_a_floor_piece_is_read_from_its_rim(
    box, camera
):
    # drawn as a designer who leaves the hidden lines out: the rim whole, of the side
    # edges and the floor only one each (the strokes' order: floor 0-3, rim 4-7, sides)
    strokes, labels = prism_sketch(camera, QUAD, 5.0, -1)
    keep = [1, 4, 5, 6, 7, 9]
    strokes, labels = [strokes[k] for k in keep], [labels[k] for k in keep]
    face = face_towards(box, (0, 0, 1))
    # which Boolean is the search's to weigh (inference/alternative.py): here the hole's
    op = fit_prism(box, face, camera, strokes, labels, Mode.SUBTRACT)
    assert op.d == pytest.approx(5.0, abs=0.3)
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in QUAD) < 0.3


def test_a_hexagonal_hole_drawn_with_its_rim_whole_and_three_side_edges_reads_as_one(box, camera):
    # a designer leaves the side edges the rim hides out: beside the reading of N from
    # the three side edges drawn (a triangle), the rim's six sides give a hexagon, and
    # the strokes are explained by the hexagon
    angles = np.radians(np.arange(6) * 60.0 + 10.0)
    hexagon = np.stack([8 * np.cos(angles), 8 * np.sin(angles), np.full(6, TOP_Z)], 1)
    strokes, labels = prism_sketch(camera, hexagon, 5.0, -1)
    keep = [6, 7, 8, 9, 10, 11, 12, 14, 16, 1]  # the rim, every other side edge, a floor side
    strokes, labels = [strokes[k] for k in keep], [labels[k] for k in keep]
    face = face_towards(box, (0, 0, 1))
    fits = prism_fits(box, face, camera, strokes, labels)
    assert sorted(len(f.operation.polygon) for f in fits) == [3, 6]
    best = min(fits, key=lambda f: sketch_fit(box, f.refined(), camera, strokes).score)
    assert len(best.operation.polygon) == 6
    # with subtract chosen (or weighed so by the search), the hole itself
    (op,) = [f.refined() for f in prism_fits(box, face, camera, strokes, labels, Mode.SUBTRACT)]
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in hexagon) < 0.3
    assert op.d == pytest.approx(5.0, abs=0.3)


def test_a_prism_drawn_with_every_line_has_one_reading(box, camera):
    strokes, labels = prism_sketch(camera, QUAD, 6.0, +1)
    assert len(prism_fits(box, face_towards(box, (0, 0, 1)), camera, strokes, labels)) == 1


def test_a_hole_drawn_with_its_rim_and_a_floor_piece_alone_is_as_deep_as_that_piece_lies(
    box, camera
):
    # the view hides every side edge: only the floor's far side shows through the rim
    strokes, labels = prism_sketch(camera, QUAD, 5.0, -1)
    keep = [1, 4, 5, 6, 7]  # a floor side, the rim
    strokes, labels = [strokes[k] for k in keep], [labels[k] for k in keep]
    op = fit_prism(box, face_towards(box, (0, 0, 1)), camera, strokes, labels, Mode.SUBTRACT)
    assert op.d == pytest.approx(5.0, abs=0.3)
    got = np.array(op.polygon)
    assert max(np.min(np.linalg.norm(got - v, axis=1)) for v in QUAD) < 0.3
