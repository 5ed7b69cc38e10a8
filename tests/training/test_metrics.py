# SPDX-License-Identifier: LGPL-2.1-or-later
"""Evaluation: the metrics on hand-made predictions, and the command's JSON and picture."""

import json

import pytest
import torch

from Sketch2CADWorkbench.cli import main
from Sketch2CADWorkbench.inference.models import Sketch2CADNet, save_checkpoint
from training.metrics import Tally, curve_classes, curve_hits, face_iou, face_overlap

EXTRUDE, BEVEL, ADDSUB, SWEEP = 0, 1, 2, 3


def test_face_iou_binarises_at_one_half_and_counts_pixels():
    pred = torch.zeros(3, 4, 4)
    label = torch.zeros(3, 4, 4)
    pred[0, :2, :2] = 0.9  # 4 pixels predicted,
    label[0, :2, :3] = 1  # 6 labelled: IoU 4 / 6
    pred[1, 0, 0], label[1, 3, 3] = 0.5, 1  # 0.5 is not above the threshold: IoU 0 / 1
    assert torch.allclose(face_iou(pred, label), torch.tensor([4 / 6, 0.0, 1.0]))  # both empty: 1
    inter, union = face_overlap(pred, label)
    assert inter.tolist() == [4, 0, 0] and union.tolist() == [6, 1, 0]


def test_curve_classes_use_one_threshold_for_two_classes_and_two_for_three():
    c = torch.tensor([0.4, 0.6, 1.4, 1.6]).reshape(1, 1, 4).expand(4, 1, 4)
    classes = curve_classes(c, torch.tensor([EXTRUDE, BEVEL, ADDSUB, SWEEP]))
    assert classes[:, 0].tolist() == [[0, 1, 1, 1], [0, 1, 1, 1], [0, 1, 1, 2], [0, 1, 1, 2]]


def test_curve_accuracy_counts_stroke_pixels_only():
    curve = torch.tensor([[[0.2, 0.9, 1.7, 5.0]]])  # classes 0, 1, 2, 2
    label = torch.tensor([[[0.0, 1.0, 1.0, 0.0]]])
    mask = torch.tensor([[[1.0, 1.0, 1.0, 0.0]]])  # the last pixel is off the strokes
    right, total = curve_hits(curve, label, mask, torch.tensor([ADDSUB]))
    assert right.tolist() == [2] and total.tolist() == [3]


def test_the_summary_averages_iou_per_sample_and_accuracy_per_stroke_pixel():
    t = Tally()
    # truth, prediction, noise level, face intersection / union, curve right / total
    t.add(
        op=[ADDSUB, ADDSUB, EXTRUDE, SWEEP],
        pred=[ADDSUB, SWEEP, EXTRUDE, SWEEP],
        noise=[1, 1, 3, 3],
        inter=[1, 3, 5, 0],
        union=[2, 4, 5, 0],
        right=[9, 1, 4, 0],
        strokes=[10, 10, 4, 0],
    )
    s = t.summary()
    assert s["n"] == 4 and s["classification_accuracy"] == 0.75
    # rows and columns for every labelled operator, the shell too
    assert s["confusion_matrix"]["rows_true_cols_predicted"][2] == [0, 0, 1, 1, 0]
    add = s["per_operator"]["addsub"]
    assert add["n"] == 2 and add["face_iou"] == pytest.approx((1 / 2 + 3 / 4) / 2)
    assert add["face_iou_pooled"] == pytest.approx(4 / 6)
    assert add["curve_accuracy"] == pytest.approx(10 / 20)
    assert s["per_operator"]["sweep"]["face_iou"] == 1.0  # nothing to find, nothing found
    assert s["per_operator"]["bevel"] == {"n": 0, "face_iou": None, "curve_accuracy": None}
    assert s["per_noise_level"]["1"]["classification_accuracy"] == 0.5
    assert s["per_noise_level"]["3"]["classification_accuracy"] == 1.0


def _weights(tmp_path, cfg) -> str:
    torch.manual_seed(0)
    run = tmp_path / "run"
    run.mkdir()
    save_checkpoint(
        run / "sketch2cad_net.pt", Sketch2CADNet(cfg).eval(), data_key={"seed": 99, "count": 1}
    )
    return str(run)


def test_the_eval_command_writes_the_required_json_and_a_picture(tiny_config, tiny_data, tmp_path):
    weights = _weights(tmp_path, tiny_config)
    out, png = tmp_path / "m.json", tmp_path / "m.png"
    assert (
        main(
            [
                "eval",
                "--data",
                str(tiny_data),
                "--weights",
                weights,
                "--json",
                str(out),
                "--report",
                str(png),
                "--latency-runs",
                "5",
            ]
        )
        == 0
    )
    r = json.loads(out.read_text())
    assert type(r["n"]) is int and r["n"] == 48
    assert isinstance(r["classification_accuracy"], float)
    assert 0 <= r["classification_accuracy"] <= 1
    assert set(r["per_operator"]) == {"extrude", "bevel", "addsub", "sweep", "shell"}
    assert r["per_operator"].pop("shell")["n"] == 0  # the set has none
    for name, d in r["per_operator"].items():
        assert type(d["n"]) is int and d["n"] > 0, name
        assert 0 <= d["face_iou"] <= 1 and 0 <= d["curve_accuracy"] <= 1
    assert sum(d["n"] for d in r["per_operator"].values()) == 48
    assert isinstance(r["latency_ms"]["networks_median"], float)
    assert r["latency_ms"]["networks_median"] > 0
    assert png.stat().st_size > 10_000


def test_eval_limits_the_samples_and_reports_missing_weights(
    tiny_config, tiny_data, tmp_path, capsys
):
    weights = _weights(tmp_path, tiny_config)
    out = tmp_path / "m.json"
    assert (
        main(
            [
                "eval",
                "--data",
                str(tiny_data),
                "--weights",
                weights,
                "--json",
                str(out),
                "--limit",
                "20",
                "--latency-runs",
                "3",
            ]
        )
        == 0
    )
    assert json.loads(out.read_text())["n"] == 20
    assert (
        main(
            [
                "eval",
                "--data",
                str(tiny_data),
                "--weights",
                str(tmp_path / "none"),
                "--json",
                str(out),
            ]
        )
        == 2
    )
    assert "sketch2cad train" in capsys.readouterr().err
