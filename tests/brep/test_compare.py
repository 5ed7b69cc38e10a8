# SPDX-License-Identifier: LGPL-2.1-or-later
"""The volume IoU behind the recovery rate: exact where OCCT's Booleans hold, and not
fooled where they fail silently."""

import cadquery as cq
import pytest

from Sketch2CADWorkbench.brep.compare import sampled_iou, volume_iou
from Sketch2CADWorkbench.brep.operators import apply_operation, build
from Sketch2CADWorkbench.brep.protocol import operation_from_dict, protocol_from_dict

# A level-1 test sample (data/test-l1, seed 10001) whose fitted bevel lies almost on the
# true one: OCCT's intersection of the two results is empty and its cuts remove nothing.
CONTEXT = {
    "format": "sketch2cad-protocol",
    "version": 1,
    "units": "mm",
    "base": {"type": "box", "size": [71.393, 60.264, 35.656]},
    "operations": [
        {
            "type": "bevel",
            "face": {"point": [0.0, 30.132, 0.0], "normal": [0, 1, 0]},
            "corner": [-35.6965, 30.132, -17.828],
            "opposite": [-35.6965, -30.132, -17.828],
            "profile": [
                [-16.215474256121162, 30.132, -17.828],
                [-20.13721363017989, 30.132, -17.828],
                [-35.6965, 30.132, -7.53275423480971],
                [-35.6965, 30.132, -4.937823482633773],
            ],
        },
        {
            "type": "addsub",
            "face": {"point": [1.184697125, 30.132, 0.555065195], "normal": [0, 1, 0]},
            "polygon": [
                [-0.3218018252090862, 30.132, 20.442827574397896],
                [10.4979286533479, 30.132, 9.910322864878424],
                [6.78637724870329, 30.132, -4.726090946412423],
                [-7.74490463449831, 30.132, -8.8300000481838],
                [-18.564635113055296, 30.132, 1.7025046613356674],
                [-14.853083708410685, 30.132, 16.338918472626524],
            ],
            "d": 5.534951316058511,
            "mode": "add",
        },
        {
            "type": "addsub",
            "face": {"point": [9.740512872, 0.0, -17.828], "normal": [0, 0, -1]},
            "polygon": [
                [6.612243693871807, 34.84983041483594, -17.828],
                [9.093368726585945, 30.446534210455987, -17.828],
                [9.674687611073395, 20.774722088721223, -17.828],
                [2.1840964653542385, 21.280236424387137, -17.828],
                [-0.05877832056550769, 31.523942609186317, -17.828],
            ],
            "d": 26.60068794023064,
            "mode": "add",
        },
    ],
}
FACE = {"point": [0.0, 0.0, 17.828], "normal": [0, 0, 1]}
CORNER, OPPOSITE = [-35.6965, -30.132, 17.828], [-35.6965, -30.132, -4.937823482633772]
TRUE_PROFILE = [
    [-35.6965, -1.673708539500364, 17.828],
    [-35.6965, -13.72672604228759, 17.828],
    [-21.839774589347332, -30.132, 17.828],
    [-11.659185448536537, -30.132, 17.828],
]
FITTED_PROFILE = [
    [-35.697, -3.844, 17.828],
    [-31.598, -15.559, 17.828],
    [-25.554, -29.261, 17.828],
    [-12.02, -30.132, 17.828],
]


def _bevelled(profile):
    op = operation_from_dict(
        {"type": "bevel", "face": FACE, "corner": CORNER, "opposite": OPPOSITE, "profile": profile}
    )
    return apply_operation(build(protocol_from_dict(CONTEXT)), op)


def test_volume_iou_of_overlapping_boxes_is_exact():
    a = cq.Solid.makeBox(10, 10, 10)
    b = cq.Solid.makeBox(10, 10, 10, cq.Vector(5, 0, 0))
    assert volume_iou(a, b) == pytest.approx(500 / 1500)
    assert volume_iou(a, a.copy()) == pytest.approx(1.0)
    assert volume_iou(a, cq.Solid.makeBox(1, 1, 1, cq.Vector(20, 0, 0))) == 0.0


def test_sampling_estimates_the_iou_of_boxes():
    a = cq.Solid.makeBox(10, 10, 10)
    b = cq.Solid.makeBox(10, 10, 10, cq.Vector(5, 0, 0))
    assert sampled_iou(a, b, 4000) == pytest.approx(1 / 3, abs=0.03)


def test_a_nearly_coincident_bevel_scores_near_one_where_the_intersection_fails():
    truth, fitted = _bevelled(TRUE_PROFILE), _bevelled(FITTED_PROFILE)
    # OCCT 7.9 gives their intersection a volume of -0.04 mm^3 (the old IoU was 0)
    iou = volume_iou(truth, fitted)
    assert iou == pytest.approx(sampled_iou(truth, fitted, 4000, seed=3), abs=0.01)
    assert iou > 0.99


def test_sampling_estimates_the_iou_of_swept_solids_whose_booleans_hold():
    # a lamp's shade and its bore, read from strokes and as designed: B-spline surfaces of
    # revolution, where OCCT's own point classifier took 0.15 s a point
    base = {
        "format": "sketch2cad-protocol",
        "version": 2,
        "units": "mm",
        "base": {"type": "box", "size": [60, 60, 10]},
        "operations": [],
    }
    top = {"point": [0.0, 0.0, 5.0], "normal": [0, 0, 1]}

    def shade(r0, r1, profile, hole):
        ops = [
            {
                "type": "sweep",
                "face": top,
                "center": [0, 0, 5],
                "r0": r0,
                "r1": r1,
                "d": 22.0,
                "profile": profile,
                "mode": "add",
            },
            {
                "type": "sweep",
                "face": {"point": [0, 0, 27.0], "normal": [0, 0, 1]},
                "center": [0, 0, 27.0],
                "r0": hole,
                "r1": 4.0,
                "d": 18.0,
                "profile": [[hole - (hole - 4) / 3, 6.0], [hole - 2 * (hole - 4) / 3, 12.0]],
                "mode": "subtract",
            },
        ]
        return build(protocol_from_dict({**base, "operations": ops}))

    truth = shade(8.0, 25.0, [[13.0, 8.0], [19.0, 15.0]], 22.0)
    read = shade(7.9, 25.6, [[13.3, 7.9], [19.4, 15.1]], 23.2)
    assert sampled_iou(truth, read, 4000) == pytest.approx(volume_iou(truth, read), abs=0.02)
