# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training: the loss goes down, runs resume exactly, the data pipeline is faithful."""

import json

import numpy as np
import pytest
import torch

from datagen.dataset import Dataset, decode_inputs
from Sketch2CADWorkbench.cli import main
from Sketch2CADWorkbench.inference.models import (
    Sketch2CADNet,
    class_weights,
    load_checkpoint,
    loss_terms,
)
from training import train as train_module
from training.data import load_pooled, split
from training.train import TrainSettings, train


def _settings(cfg, steps, **kw):
    return TrainSettings(
        steps=steps,
        batch_size=8,
        lr=1e-2,
        warmup_steps=5,
        threads=1,
        checkpoint_minutes=60.0,
        log_every=5,
        val_fraction=0.25,
        model=cfg,
        **kw,
    )


def _loss_on(model, data_dir, out):
    """Mean losses (classification, face, curve) over the whole tiny set (eval mode, no
    augmentation)."""
    data = load_pooled(Dataset(data_dir), model, out)
    model.eval()
    with torch.no_grad():
        x, face, curve, mask, op = data.batch(torch.arange(len(data)), "cpu")
        w = class_weights(torch.bincount(op, minlength=4))
        return np.array([float(t) for t in loss_terms(model, model(x), op, face, curve, mask, w)])


def test_a_few_steps_reduce_the_loss_and_leave_the_run_files(tiny_config, tiny_data, tmp_path):
    torch.manual_seed(0)
    before = _loss_on(Sketch2CADNet(tiny_config), tiny_data, tmp_path)
    final = train(tiny_data, tmp_path, _settings(tiny_config, 80))
    model, ckpt = load_checkpoint(final)
    after = _loss_on(model, tiny_data, tmp_path)
    assert after.sum() < 0.85 * before.sum() and after[1:].sum() < 0.7 * before[1:].sum()
    assert ckpt["trained_steps"] == 80 and ckpt["class_counts"] == [5, 5, 18, 8]
    for name in ("checkpoint.pt", "log.jsonl", "loss_curves.png", "data-cache-16.pt"):
        assert (tmp_path / name).stat().st_size > 0, name
    rows = [json.loads(line) for line in (tmp_path / "log.jsonl").read_text().splitlines()]
    kinds = [r["kind"] for r in rows]
    assert kinds[0] == "event" and kinds.count("train") == 16
    val = [r for r in rows if r["kind"] == "val"]
    assert len(val) == 80 // 5  # after each epoch (5 steps) that another follows, and at the end
    per = val[-1]["per_operator"]  # every labelled operator; the set has no shell
    assert set(per) == {"extrude", "bevel", "addsub", "sweep", "shell"} and per["shell"]["n"] == 0


def test_a_run_interrupted_and_resumed_ends_exactly_where_an_uninterrupted_one_does(
    tiny_config, tiny_data, tmp_path, monkeypatch
):
    whole = train(tiny_data, tmp_path / "whole", _settings(tiny_config, 12))
    calls = []

    def interrupting(*args):  # Ctrl-C in step 7 (the 6th call validated epoch 1)
        calls.append(1)
        if len(calls) == 8:
            raise KeyboardInterrupt
        return loss_terms(*args)

    monkeypatch.setattr(train_module, "loss_terms", interrupting)
    with pytest.raises(KeyboardInterrupt):
        train(tiny_data, tmp_path / "split", _settings(tiny_config, 12))
    assert load_checkpoint(tmp_path / "split" / "checkpoint.pt")[1]["state"]["step"] == 6
    resumed = train(tiny_data, tmp_path / "split", _settings(tiny_config, 12))
    a, _ = load_checkpoint(whole)
    b, ckpt = load_checkpoint(resumed)
    assert ckpt["trained_steps"] == 12
    assert all(
        torch.equal(p, q)
        for p, q in zip(a.state_dict().values(), b.state_dict().values(), strict=True)
    )
    events = [
        json.loads(line)
        for line in (tmp_path / "split" / "log.jsonl").read_text().splitlines()
        if '"event"' in line
    ]
    assert [e["what"] for e in events] == ["start", "interrupted", "resume", "end"]


def test_resuming_on_another_data_set_is_refused(tiny_config, tiny_data, tmp_path, write_dataset):
    train(tiny_data, tmp_path / "run", _settings(tiny_config, 2))
    other = write_dataset(tmp_path / "other", 24, 8, seed=3)
    with pytest.raises(ValueError, match="another data set"):
        train(other, tmp_path / "run", _settings(tiny_config, 4))


def test_the_pooled_batch_matches_the_models_pooling_of_the_stored_maps(
    tiny_config, tiny_data, tmp_path
):
    model = Sketch2CADNet(tiny_config)
    ds = Dataset(tiny_data)
    data = load_pooled(ds, model, tmp_path)
    x, face, curve, mask, op = data.batch(torch.arange(4), "cpu")
    a = ds.shard_arrays(0)
    expect = model.pool(torch.from_numpy(decode_inputs(a, slice(0, 4))))
    assert torch.allclose(x, expect, atol=0.5 / 127.5 + 1e-6)  # 8-bit storage
    assert torch.equal(face, torch.from_numpy(a["face_label"][:4]).float())
    assert torch.equal(curve, torch.from_numpy(a["curve_label"][:4]).float())
    assert torch.equal(mask, torch.from_numpy(a["stroke_mask"][:4]).float())
    assert op.tolist() == a["op_type"][:4].tolist()


def test_a_mirrored_sample_is_the_pooled_mirror_image_with_normal_x_negated(
    tiny_config, tiny_data, tmp_path
):
    model = Sketch2CADNet(tiny_config)
    ds = Dataset(tiny_data)
    data = load_pooled(ds, model, tmp_path)
    x, face, _curve, _mask, _ = data.batch(torch.arange(4), "cpu", flip=torch.ones(4, dtype=bool))
    full = torch.from_numpy(decode_inputs(ds.shard_arrays(0), slice(0, 4))).flip(-1)
    fg = full[:, 2:].sum(1) > 0
    full[:, 2] = torch.where(fg, 2 - full[:, 2], 0)  # n_x -> -n_x on the foreground
    assert torch.allclose(x, model.pool(full), atol=1.5 / 127.5)
    assert torch.equal(
        face, torch.from_numpy(ds.shard_arrays(0)["face_label"][:4]).float().flip(-1)
    )


def test_the_validation_split_keeps_contexts_whole():
    assert split(100, 0.05, 4) == (slice(0, 92), slice(92, 100))
    assert split(6, 0.5, 4) == (slice(0, 6), slice(6, 6))  # too small to hold anything out


def test_the_train_command_runs_and_reports_a_missing_data_set(tiny_data, tmp_path, capsys):
    assert main(["train", "--data", str(tmp_path / "nothing"), "--out", str(tmp_path / "r")]) == 2
    assert "no manifest.json" in capsys.readouterr().err
    assert (
        main(
            [
                "train",
                "--data",
                str(tiny_data),
                "--out",
                str(tmp_path / "run"),
                "--steps",
                "3",
                "--batch-size",
                "4",
                "--threads",
                "1",
                "--internal-size",
                "16",
                "--widths",
                "4",
                "8",
            ]
        )
        == 0
    )
    _, ckpt = load_checkpoint(tmp_path / "run" / "sketch2cad_net.pt")
    assert ckpt["config"]["internal_size"] == 16 and ckpt["trained_steps"] == 3
    assert np.isfinite(ckpt["validation"]["cls"])
