# SPDX-License-Identifier: LGPL-2.1-or-later
"""The model card's structured-heads section: one row per reading of each held-out set."""
from Sketch2CADWorkbench.cli.model_card import HEADS_HEADING, OPS, heads_section


def _summary(face, curve, cls=0.99, n=400):
    return {"n": n, "classification_accuracy": cls,
            "per_operator": {op: {"n": 100, "face_iou": face, "curve_accuracy": curve}
                             for op in OPS}}


def test_the_heads_section_has_a_row_per_reading_and_the_papers_row():
    scores = {"data/test-l1": {"data": {"seed": 10001}, "unet": _summary(0.809, 0.752),
                               "head": _summary(0.95, 0.97, cls=0.995)}}
    alone = {"data/test-l1": {"unet": _summary(0.809, 0.752), "head": _summary(0.9, 0.9)}}
    lines = heads_section([(scores, None), (alone, {"config": {"layers": 0}, "model": {},
                                                    "settings": {"epochs": 2, "threads": 1},
                                                    "log": [{"seconds": 60}]})])
    assert lines[0] == HEADS_HEADING
    rows = [ln for ln in lines if ln.startswith("| test-l1")]
    assert len(rows) == 3  # the U-Net's row once
    assert "| unet | 99.0 | 80.9 / 75.2 |" in rows[0]
    assert "| head | 99.5 | 95.0 / 97.0 |" in rows[1]
    assert "| head, 0 attention layers | 99.0 | 90.0 / 90.0 |" in rows[2]
    assert any("0 attention layers: 0 parameters" in ln for ln in lines)
    assert any(ln.startswith("| paper, Table 1 |") for ln in lines)
