# SPDX-License-Identifier: LGPL-2.1-or-later
"""The model card's structured-heads section: one row per reading of each held-out set,
end to end beside the U-Net, and the head shipped only with the U-Net it was trained on."""

import json

from Sketch2CADWorkbench.cli.model_card import (
    GUARD_HEADING,
    HEADS_HEADING,
    OPS,
    SHIPPED_HEAD_HEADING,
    end_to_end,
    heads_section,
    replace_heads_section,
)
from Sketch2CADWorkbench.inference.weights import HEAD_NAME


def _summary(face, curve, cls=0.99, n=400):
    return {
        "n": n,
        "classification_accuracy": cls,
        "per_operator": {op: {"n": 100, "face_iou": face, "curve_accuracy": curve} for op in OPS},
    }


def test_the_heads_section_has_a_row_per_reading_and_the_papers_row():
    scores = {
        "data/test-l1": {
            "data": {"seed": 10001},
            "unet": _summary(0.809, 0.752),
            "head": _summary(0.95, 0.97, cls=0.995),
        }
    }
    alone = {"data/test-l1": {"unet": _summary(0.809, 0.752), "head": _summary(0.9, 0.9)}}
    lines = heads_section(
        [
            (scores, None),
            (
                alone,
                {
                    "config": {"layers": 0, "width": 96},
                    "model": {},
                    "settings": {"epochs": 2, "threads": 1},
                    "log": [{"seconds": 60}],
                },
            ),
        ]
    )
    assert lines[0] == HEADS_HEADING
    rows = [ln for ln in lines if ln.startswith("| test-l1")]
    assert len(rows) == 3  # the U-Net's row once
    assert "| unet | 99.0 | 80.9 / 75.2 |" in rows[0]
    assert "| head | 99.5 | 95.0 / 97.0 |" in rows[1]
    assert "| head, 0 attention layers, width 96 | 99.0 | 90.0 / 90.0 |" in rows[2]
    assert any("0 attention layers, width 96: 0 parameters" in ln for ln in lines)
    assert any(ln.startswith("| paper, Table 1 |") for ln in lines)


def test_a_head_trained_on_several_sets_names_each_with_its_count():
    head = {
        "config": {"layers": 3, "width": 128},
        "model": {},
        "settings": {"epochs": 20, "threads": 1},
        "log": [{"seconds": 60}],
        "train_samples": 12,
        "data": "data/a + data/b",
        "data_counts": {"data/a": 8, "data/b": 4},
    }
    scores = {"data/t-l1": {"unet": _summary(0.8, 0.7), "head": _summary(0.9, 0.9)}}
    lines = heads_section([(scores, head)])
    assert any(
        "20 epochs of 12 samples of the union of 8 of `data/a`, 4 of `data/b` in" in ln
        for ln in lines
    )
    one = {**head, "train_samples": 8, "data": "data/a", "data_counts": {"data/a": 8}}
    assert any(
        "20 epochs of 8 samples of `data/a` in" in ln for ln in heads_section([(scores, one)])
    )


def _recovery(strict, flip, n=100):
    per = {
        op: {"recovery_rate": strict, "recovery_rate_with_flip": flip, "recovery_n": n}
        for op in OPS
    }
    return {"per_operator": per, "interpret_median_ms": 250.0}


def test_the_end_to_end_table_has_each_readings_recovery_per_data_set():
    lines = end_to_end(
        {"head-recovery-l1": {"unet": _recovery(0.9, 0.95), "head": _recovery(0.92, 0.97)}}
    )
    rows = [ln for ln in lines if ln.startswith("| head-recovery-l1")]
    assert rows[0].startswith("| head-recovery-l1 | unet | 90.0 [95.0] (100) |")
    assert rows[1].startswith("| head-recovery-l1 | head | 92.0 [97.0] (100) |")


def test_the_heads_section_is_replaced_in_place_or_put_before_the_guard():
    new = [SHIPPED_HEAD_HEADING, "new"]
    card = f"# Card\n\n{HEADS_HEADING}\nold\n\n{GUARD_HEADING}\nguard\n"
    assert (
        replace_heads_section(card, new)
        == f"# Card\n\n{SHIPPED_HEAD_HEADING}\nnew\n{GUARD_HEADING}\nguard\n"
    )
    bare = f"# Card\n\n{GUARD_HEADING}\nguard\n"
    assert (
        replace_heads_section(bare, new)
        == f"# Card\n\n{SHIPPED_HEAD_HEADING}\nnew\n{GUARD_HEADING}\nguard\n"
    )


def test_a_head_ships_only_when_trained_on_the_shipped_unet(tmp_path, monkeypatch, capsys):
    import torch

    from Sketch2CADWorkbench.cli import main, model_card
    from Sketch2CADWorkbench.inference.head.checkpoint import sha256_of

    weights = tmp_path / "weights"
    weights.mkdir()
    (weights / "sketch2cad_net.pt").write_bytes(b"the shipped U-Net")
    (weights / "MODEL_CARD.md").write_text(f"# Card\n\n{GUARD_HEADING}\nguard\n")
    monkeypatch.setattr(model_card, "WEIGHTS", weights)
    run = tmp_path / "run"
    run.mkdir()
    (run / "scores.json").write_text(
        json.dumps({"data/t-l1": {"unet": _summary(0.8, 0.7), "head": _summary(0.9, 0.9)}})
    )
    head = {
        "config": {"layers": 3},
        "model": {},
        "settings": {"epochs": 2, "threads": 1},
        "log": [{"seconds": 60}],
        "unet_sha256": "0" * 64,
    }
    torch.save(head, run / HEAD_NAME)
    args = ["model-card", "--heads", str(run / "scores.json"), "--ship-head"]
    assert main(args) == 2 and "not a head trained on" in capsys.readouterr().err
    assert not (weights / HEAD_NAME).exists()
    torch.save({**head, "unet_sha256": sha256_of(weights / "sketch2cad_net.pt")}, run / HEAD_NAME)
    assert main(args) == 0
    assert (weights / HEAD_NAME).read_bytes() == (run / HEAD_NAME).read_bytes()
    card = (weights / "MODEL_CARD.md").read_text()
    assert SHIPPED_HEAD_HEADING in card and card.rstrip().endswith("guard")


def test_a_new_unet_drops_a_shipped_head_trained_on_another(tmp_path, monkeypatch):
    import torch

    from Sketch2CADWorkbench.cli import model_card
    from Sketch2CADWorkbench.inference.head.checkpoint import sha256_of

    monkeypatch.setattr(model_card, "WEIGHTS", tmp_path)
    (tmp_path / "sketch2cad_net.pt").write_bytes(b"the new U-Net")
    torch.save({"unet_sha256": sha256_of(tmp_path / "sketch2cad_net.pt")}, tmp_path / HEAD_NAME)
    model_card._drop_stale_head()
    assert (tmp_path / HEAD_NAME).exists()
    torch.save({"unet_sha256": "0" * 64}, tmp_path / HEAD_NAME)
    model_card._drop_stale_head()
    assert not (tmp_path / HEAD_NAME).exists()
