# SPDX-License-Identifier: LGPL-2.1-or-later
"""A reading's fit to the strokes: when it is flagged as doubtful."""

from Sketch2CADWorkbench.brep.protocol import OperatorType


def test_a_reading_whose_sketch_and_strokes_do_not_explain_each_other_is_flagged():
    from dataclasses import replace as with_

    from Sketch2CADWorkbench.inference.interpret import Interpretation
    from Sketch2CADWorkbench.inference.reading import DOUBT, SketchFit

    ok = SketchFit(**{k: 0.0 for k in SketchFit.MEASURES if k != "confidence"}, confidence=1.0)
    ok = with_(ok, **{k: v for k, v in DOUBT.items() if k != "confidence"})
    base = Interpretation((), None, OperatorType.BEVEL, {}, 0, [], None, fit=ok)
    assert not base.doubtful and base.doubt() == ""
    for name, limit in DOUBT.items():
        far = with_(
            base, fit=with_(ok, **{name: limit - 0.2 if name == "confidence" else limit + 0.2})
        )
        assert far.doubtful and far.fit.passed() == [name]
        assert far.doubt().startswith("the strokes do not look much like this bevel: ")
