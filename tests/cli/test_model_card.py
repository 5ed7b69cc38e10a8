# SPDX-License-Identifier: LGPL-2.1-or-later
"""The model card: written whole from the shipped files and the figures stored in
docs/eval/, the committed card exactly that; the heads' ablation with one row per reading
of each held-out set; a head shipped only with the U-Net it was trained on."""

import json
import re
import shutil

import pytest
import torch

from Sketch2CADWorkbench.cli import main, model_card
from Sketch2CADWorkbench.cli.model_card import OPS, card, end_to_end, heads_section
from Sketch2CADWorkbench.inference.head.checkpoint import sha256_of
from Sketch2CADWorkbench.inference.weights import HEAD_NAME, WEIGHTS_NAME


def test_the_committed_card_is_what_model_card_writes_from_the_stored_figures():
    committed = (model_card.WEIGHTS / "MODEL_CARD.md").read_text()
    assert committed == card(), "run `sketch2cad model-card` and commit MODEL_CARD.md"


def test_the_card_states_the_current_figures_not_their_history():
    text = card()
    for pattern in (r"\bstop \d", r"#\d", r"\blater at\b", r"\bscratch\b"):
        assert not re.search(pattern, text, re.IGNORECASE), pattern
    assert f"`{sha256_of(model_card.WEIGHTS / WEIGHTS_NAME)}`" in text
    pipeline = json.loads((model_card.EVAL / "pipeline.json").read_text())
    for name in pipeline["sets"]:
        assert f"| {name} |" in text, name


def _summary(face, curve, cls=0.99, n=400):
    return {
        "n": n,
        "classification_accuracy": cls,
        "per_operator": {op: {"n": 100, "face_iou": face, "curve_accuracy": curve} for op in OPS},
    }


def _head(layers, width, data_counts, **more):
    return {
        "layers": layers,
        "width": width,
        "parameters": 10,
        "config": {"layers": layers, "width": width},
        "epochs": 20,
        "train_samples": sum(data_counts.values()),
        "data": " + ".join(data_counts),
        "data_counts": data_counts,
        "minutes": 1.0,
        **more,
    }


def test_the_heads_section_has_a_row_per_reading_and_the_papers_row():
    heads = {
        "commands": ["sketch2cad train-head ..."],
        "runs": [
            {
                "head": _head(3, 128, {"data/a": 8, "data/b": 4}, threads=1),
                "scores": {
                    "data/test-l1": {
                        "unet": _summary(0.809, 0.752),
                        "head": _summary(0.95, 0.97, cls=0.995),
                    }
                },
            },
            {
                "head": _head(0, 96, {"data/a": 8}),
                "scores": {"data/test-l1": {"head": _summary(0.9, 0.9)}},
            },
        ],
    }
    lines = heads_section(heads)
    rows = [ln for ln in lines if ln.startswith("| test-l1")]
    assert len(rows) == 3  # the U-Net's row once
    assert "| U-Net alone | 99.0 | 80.9 / 75.2 |" in rows[0]
    assert "| head, 3 attention layers, width 128 | 99.5 | 95.0 / 97.0 |" in rows[1]
    assert "| head, 0 attention layers, width 96 | 99.0 | 90.0 / 90.0 |" in rows[2]
    assert any(
        "(shipped): 10 parameters" in ln
        and "20 epochs of 12 samples of the union of 8 of `data/a`, 4 of `data/b` in 1.0 "
        "min on 1 torch thread(s)"
        in ln
        for ln in lines
    )
    assert any("20 epochs of 8 samples of `data/a` in 1.0 min" in ln for ln in lines)
    assert any(ln.startswith("| paper, Table 1 (level 1) |") for ln in lines)


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


@pytest.fixture
def package(tmp_path, monkeypatch):
    """A copy of the shipped U-Net and the stored figures, in place of the package's."""
    weights, stored = tmp_path / "weights", tmp_path / "eval"
    weights.mkdir()
    shutil.copyfile(model_card.WEIGHTS / WEIGHTS_NAME, weights / WEIGHTS_NAME)
    shutil.copytree(model_card.EVAL, stored)
    monkeypatch.setattr(model_card, "WEIGHTS", weights)
    monkeypatch.setattr(model_card, "EVAL", stored)
    return weights, stored


def _checkpoint(**more) -> dict:
    """A head checkpoint as `sketch2cad train-head` writes it, its features another
    U-Net's than the shipped one."""
    return {
        "config": {"layers": 3, "width": 64},
        "model": {"w": torch.zeros(3)},
        "settings": {"epochs": 2, "threads": 1},
        "log": [{"seconds": 60}],
        "train_samples": 5,
        "data": "data/t",
        "data_counts": {"data/t": 5},
        "unet_sha256": "0" * 64,
        **more,
    }


def test_a_head_ships_only_when_trained_on_the_shipped_unet(package, tmp_path, capsys):
    weights, stored = package
    run = tmp_path / "run"
    run.mkdir()
    (run / "scores.json").write_text(
        json.dumps({"data/t-l1": {"unet": _summary(0.8, 0.7), "head": _summary(0.9, 0.9)}})
    )
    head = _checkpoint()
    torch.save(head, run / HEAD_NAME)
    before = (stored / "heads.json").read_text()
    args = ["model-card", "--heads", str(run / "scores.json"), "--ship-head"]
    assert main(args) == 2 and "not a head trained on" in capsys.readouterr().err
    assert not (weights / HEAD_NAME).exists()
    assert (stored / "heads.json").read_text() == before  # nothing stored
    torch.save({**head, "unet_sha256": sha256_of(weights / WEIGHTS_NAME)}, run / HEAD_NAME)
    assert main(args) == 0
    assert (weights / HEAD_NAME).read_bytes() == (run / HEAD_NAME).read_bytes()
    assert json.loads((stored / "heads.json").read_text())["runs"][0]["head"]["parameters"] == 3
    text = (weights / "MODEL_CARD.md").read_text()
    assert f"`{sha256_of(weights / HEAD_NAME)}`" in text
    assert "| t-l1 | 400 | head, 3 attention layers, width 64 | 99.0 | 90.0 / 90.0 |" in text


def test_a_fine_tuned_head_ships_with_its_figures_only_on_the_shipped_unet(package, tmp_path):
    weights, stored = package
    run = tmp_path / "head5"
    run.mkdir()
    scores = {"data/t5-l1": {"unet": _summary(0.8, 0.7), "head": _summary(0.9, 0.9, cls=0.983)}}
    (run / "scores.json").write_text(json.dumps(scores))
    head = _checkpoint(
        config={"layers": 3, "width": 64, "classes": 5},
        settings={"epochs": 10, "threads": 2, "init": "runs/head/sketch2cad_head.pt"},
    )
    torch.save(head, run / HEAD_NAME)
    before = (stored / "tuned.json").read_text()
    args = ["model-card", "--tuned", str(run / "scores.json")]
    assert main(args) == 2  # trained on another U-Net's features
    assert not (weights / HEAD_NAME).exists()
    assert (stored / "tuned.json").read_text() == before  # nothing stored
    torch.save({**head, "unet_sha256": sha256_of(weights / WEIGHTS_NAME)}, run / HEAD_NAME)
    assert main(args) == 0
    assert (weights / HEAD_NAME).read_bytes() == (run / HEAD_NAME).read_bytes()
    tuned = json.loads((stored / "tuned.json").read_text())
    assert tuned["head"]["init"] == "runs/head/sketch2cad_head.pt"
    assert tuned["scores"] == scores
    text = (weights / "MODEL_CARD.md").read_text()
    assert "## The shipped head: five operators, two hands" in text
    assert "| t5-l1 | 400 | head (shipped) | 98.3 | 90.0 / 90.0 |" in text
    assert "--epochs 10 --width 128 --lr 2e-4" in text  # the command that trained it


def test_options_that_go_together_are_asked_for_together(package, capsys):
    assert main(["model-card", "--ship-head"]) == 2
    assert "--ship-head and --head-recovery go with --heads" in capsys.readouterr().err
    assert main(["model-card", "--run", "runs/main"]) == 2
    assert "give --run with --eval" in capsys.readouterr().err
    assert not (package[0] / "MODEL_CARD.md").exists()


def test_a_new_unet_drops_a_shipped_head_trained_on_another(tmp_path, monkeypatch):
    monkeypatch.setattr(model_card, "WEIGHTS", tmp_path)
    (tmp_path / WEIGHTS_NAME).write_bytes(b"the new U-Net")
    torch.save({"unet_sha256": sha256_of(tmp_path / WEIGHTS_NAME)}, tmp_path / HEAD_NAME)
    model_card._drop_stale_head()
    assert (tmp_path / HEAD_NAME).exists()
    torch.save({"unet_sha256": "0" * 64}, tmp_path / HEAD_NAME)
    model_card._drop_stale_head()
    assert not (tmp_path / HEAD_NAME).exists()
