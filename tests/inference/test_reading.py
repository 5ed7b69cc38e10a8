# SPDX-License-Identifier: LGPL-2.1-or-later
"""A reading's fit to the strokes: when it is flagged as doubtful."""

from dataclasses import replace

import numpy as np

from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference.fitting.verify import SketchFit
from Sketch2CADWorkbench.inference.interpret import Interpretation
from Sketch2CADWorkbench.inference.reading import DOUBT, GOOD_FIT_PX, doubts


def off_by(strokes_px: float, sketch_px: float) -> SketchFit:
    """A fit whose strokes lie `strokes_px` from the sketch and the sketch `sketch_px`
    from the strokes, everywhere."""
    return SketchFit(np.full(20, strokes_px), np.full(10, sketch_px), np.zeros(0))


def test_a_reading_whose_sketch_and_strokes_do_not_explain_each_other_is_flagged():
    limits = {k: v for k, v in DOUBT.items() if k != "confidence"}
    at = off_by(limits.get("strokes_off_px", 0.0), limits.get("sketch_off_px", 0.0))
    base = Interpretation((), None, OperatorType.BEVEL, {"bevel": 1.0}, 0, [], None, fit=at)
    assert not base.doubtful and base.doubt() == ""
    beyond = {
        "strokes_off_px": off_by(limits.get("strokes_off_px", 0.0) + 0.2, 0.0),
        "sketch_off_px": off_by(0.0, limits.get("sketch_off_px", 0.0) + 0.2),
    }
    for name, limit in DOUBT.items():
        if name == "confidence":
            far = replace(base, probabilities={"bevel": limit - 0.2})
        else:
            far = replace(base, fit=beyond[name])
        assert far.doubtful and doubts(far.measures()) == [name]
        assert far.doubt().startswith("the strokes do not look much like this bevel: ")


def test_a_reading_of_an_operator_the_classifier_all_but_rules_out_is_flagged():
    # the networks gave a sweep 1e-5 (a scribble that fits no likely operator, which the
    # search read as a sweep), and its sketch lies a few pixels from the strokes
    loose = off_by(GOOD_FIT_PX + 1.0, GOOD_FIT_PX + 1.0)
    got = Interpretation((), None, OperatorType.SWEEP, {"sweep": 1e-5}, 0, [], None, fit=loose)
    assert got.doubtful and doubts(got.measures()) == ["confidence"]
    assert "the networks give a sweep a probability of only 1e-05" in got.doubt()
    assert not replace(got, probabilities={"sweep": 0.6}).doubtful


def test_a_clear_fit_of_an_operator_the_classifier_all_but_rules_out_is_not_flagged():
    # a hole drawn without its hidden lines, which the networks take for an extrusion:
    # its prism fits the strokes within a pixel or two, as no scribble's reading does
    close = off_by(GOOD_FIT_PX - 1.0, GOOD_FIT_PX - 1.0)
    got = Interpretation((), None, OperatorType.ADDSUB, {"addsub": 1e-9}, 0, [], None, fit=close)
    assert not got.doubtful and got.doubt() == ""
