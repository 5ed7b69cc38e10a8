# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training the structured heads: they learn stroke roles and the base face on the frozen
U-Net's features, resume after an epoch, train on the union of several data sets, and are
scored beside the U-Net with the paper's metrics on the same samples."""

import json
import shutil

import numpy as np
import pytest
import torch
from network_fixtures import SIZE, synthetic_record

from datagen.dataset import FORMAT, VERSION, Record, write_shard
from Sketch2CADWorkbench.cli import main
from Sketch2CADWorkbench.inference.head.checkpoint import load_head, save_head
from Sketch2CADWorkbench.inference.head.model import HeadConfig, StructureHead
from Sketch2CADWorkbench.inference.head.tokens import feature_channels
from Sketch2CADWorkbench.inference.models import Sketch2CADNet, load_checkpoint, save_checkpoint
from Sketch2CADWorkbench.inference.weights import HEAD_NAME
from training.heads import HeadSettings, evaluate_head, extract, train_head


def _with_strokes(record: Record) -> Record:
    """The toy sample's four strokes as polylines with their curve labels: each drawn
    stroke is a row or column run of the sketch (network_fixtures.synthetic_record)."""
    sketch, curve = record.arrays["sketch"], record.arrays["curve_label"]
    rows = [r for r in range(SIZE) if sketch[r].sum() > 2]
    cols = [c for c in range(SIZE) if sketch[:, c].sum() > 2]
    strokes, parts = [], []
    for r in rows:
        c = np.nonzero(sketch[r])[0]
        strokes.append([[c[0] + 0.5, r + 0.5], [c[-1] + 0.5, r + 0.5]])
        parts.append(int(curve[r, c[len(c) // 2]]))
    for c in cols:
        r = np.nonzero(sketch[:, c])[0]
        strokes.append([[c + 0.5, r[0] + 0.5], [c + 0.5, r[-1] + 0.5]])
        parts.append(int(curve[r[len(r) // 2], c]))
    return Record(record.arrays, {"strokes": strokes, "stroke_parts": parts})


@pytest.fixture(scope="module")
def stroke_data(tmp_path_factory):
    """64 toy samples with stroke polylines (a shell among each 8, which the U-Net has
    no class for), in 2 shards, and a tiny U-Net file."""
    folder = tmp_path_factory.mktemp("stroke-data")
    rng = np.random.default_rng(0)
    ops = [0, 1, 2, 2, 2, 3, 3, 4]
    records = [_with_strokes(synthetic_record(rng, ops[i % 8], 1)) for i in range(64)]
    for k in range(2):
        write_shard(folder, k, records[32 * k : 32 * (k + 1)])
    (folder / "manifest.json").write_text(
        json.dumps(
            {
                "format": FORMAT,
                "version": VERSION,
                "count": 64,
                "seed": 0,
                "noise": "1",
                "image_size": SIZE,
                "shard_size": 32,
                "per_context": 4,
                "shards": ["shard-00000.npz", "shard-00001.npz"],
            }
        )
    )
    torch.manual_seed(0)
    from Sketch2CADWorkbench.inference.models import ModelConfig

    net = Sketch2CADNet(
        ModelConfig(
            image_size=SIZE, internal_size=SIZE // 2, widths=(8, 16, 32), classifier_hidden=8
        )
    )
    save_checkpoint(folder / "unet.pt", net)
    return folder


def _settings(epochs):
    return HeadSettings(
        epochs=epochs,
        batch_size=16,
        lr=3e-3,
        threads=1,
        head=HeadConfig(width=32, layers=1, dropout=0.0),
    )


def test_targets_follow_the_labels(stroke_data):
    from Sketch2CADWorkbench.inference.weights import load_model

    model, _ = load_model(stroke_data / "unet.pt")
    items = extract(stroke_data, model, limit=40)
    assert len(items) == 40
    for it in items:
        assert len(it.roles) == len(it.tokens.stroke) == 4
        # the base face token is the face F~ covers
        assert it.face >= 0 and len(it.tokens.face_ids) == 2


def test_the_head_learns_roles_and_faces_and_beats_chance(stroke_data, tmp_path):
    final = train_head(stroke_data, tmp_path / "run", _settings(25), stroke_data / "unet.pt")
    _, ckpt = load_head(final)
    log = ckpt["log"]
    assert log[-1]["role"] < 0.5 * log[0]["role"] and log[-1]["face"] < 0.5 * log[0]["face"]
    r = evaluate_head(stroke_data, final, stroke_data / "unet.pt")
    # the U-Net is scored on the samples of its four classes, the head on all five
    assert r["unet"]["n"] == 56 and r["head"]["n"] == 64
    assert r["unet"]["per_operator"]["shell"]["n"] == 0
    head = r["head"]["per_operator"]
    assert head["shell"]["n"] == 8
    # on its (learnable) training set the head reads every face and role (the toy bevel
    # has two strokes of each role, where decoding allows one l: 3 of 4 at best)
    assert all(head[k]["face_iou"] > 0.9 for k in head)
    assert all(head[k]["curve_accuracy"] > 0.9 for k in head if k != "bevel")
    assert head["bevel"]["curve_accuracy"] >= 0.7


def test_a_rerun_resumes_after_the_last_epoch(stroke_data, tmp_path, capsys):
    out = tmp_path / "run"
    train_head(stroke_data, out, _settings(2), stroke_data / "unet.pt")
    assert (out / "tokens" / stroke_data.name / "tokens-00000.pt").exists()
    train_head(stroke_data, out, _settings(3), stroke_data / "unet.pt")
    assert "resuming after epoch 2" in capsys.readouterr().out
    _, ckpt = load_head(out / "head-checkpoint.pt")
    assert ckpt["epoch"] == 3 and [row["epoch"] for row in ckpt["log"]] == [1, 2, 3]


def test_the_command_prints_both_rows(stroke_data, tmp_path, capsys):
    code = main(
        [
            "train-head",
            "--data",
            str(stroke_data),
            "--out",
            str(tmp_path / "run"),
            "--weights",
            str(stroke_data / "unet.pt"),
            "--epochs",
            "1",
            "--width",
            "16",
            "--layers",
            "1",
            "--eval",
            str(stroke_data),
            "--json",
            str(tmp_path / "s.json"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 0 and "unet   cls" in out and "head   cls" in out
    assert set(json.loads((tmp_path / "s.json").read_text())[str(stroke_data)]) >= {"unet", "head"}


def test_the_command_says_what_is_missing(tmp_path, capsys):
    assert (
        main(["train-head", "--data", str(tmp_path / "none"), "--out", str(tmp_path / "run")]) == 2
    )
    assert "sketch2cad train-head: error" in capsys.readouterr().err


def test_runs_sharing_a_token_cache_read_the_unet_once(stroke_data, tmp_path, monkeypatch):
    import training.heads as th

    cache = tmp_path / "tokens"
    train_head(stroke_data, tmp_path / "a", _settings(1), stroke_data / "unet.pt", cache)

    def no_unet(*args, **kwargs):
        raise AssertionError("the U-Net ran again")

    monkeypatch.setattr(th, "_sample_items", no_unet)
    train_head(stroke_data, tmp_path / "b", _settings(1), stroke_data / "unet.pt", cache)
    other = tmp_path / "other-unet.pt"  # another U-Net's features are not reused
    torch.manual_seed(1)
    save_checkpoint(other, Sketch2CADNet(load_checkpoint(stroke_data / "unet.pt")[0].config))
    with pytest.raises(AssertionError, match="ran again"):
        train_head(stroke_data, tmp_path / "c", _settings(1), other, cache)


def test_eval_scores_a_shipped_heads_choices_beside_the_unets_maps(stroke_data, tmp_path):
    # the default predictor reads with a head lying beside the weights, so `sketch2cad
    # eval` scores its painted F and C too, with the paper's metrics
    run = tmp_path / "run"
    run.mkdir()
    shutil.copy(stroke_data / "unet.pt", run / "sketch2cad_net.pt")
    net, _ = load_checkpoint(run / "sketch2cad_net.pt")
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    save_head(run / HEAD_NAME, head)
    out = tmp_path / "m.json"
    assert (
        main(
            [
                "eval",
                "--data",
                str(stroke_data),
                "--weights",
                str(run),
                "--json",
                str(out),
                "--limit",
                "16",
                "--latency-runs",
                "2",
                "--recovery",
                "0",
            ]
        )
        == 0
    )
    r = json.loads(out.read_text())
    assert r["structured"]["n"] == 16 and 0 <= r["structured"]["classification_accuracy"] <= 1
    for name, d in r["structured"]["per_operator"].items():
        if d["n"]:
            assert 0 <= d["face_iou"] <= 1 and 0 <= d["curve_accuracy"] <= 1, name
    (run / HEAD_NAME).unlink()
    assert (
        main(
            [
                "eval",
                "--data",
                str(stroke_data),
                "--weights",
                str(run),
                "--json",
                str(out),
                "--limit",
                "16",
                "--latency-runs",
                "2",
                "--recovery",
                "0",
            ]
        )
        == 0
    )
    assert "structured" not in json.loads(out.read_text())


def test_eval_reads_the_head_from_the_unets_one_pass_over_the_data(
    stroke_data, tmp_path, monkeypatch
):
    # scoring the shipped head beside the U-Net's maps costs no second pass of the U-Net
    run = tmp_path / "run"
    run.mkdir()
    shutil.copy(stroke_data / "unet.pt", run / "sketch2cad_net.pt")
    net, _ = load_checkpoint(run / "sketch2cad_net.pt")
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    calls = []
    original = Sketch2CADNet.features
    monkeypatch.setattr(
        Sketch2CADNet, "features", lambda self, x: calls.append(len(x)) or original(self, x)
    )
    args = [
        "eval",
        "--data",
        str(stroke_data),
        "--weights",
        str(run),
        "--json",
        str(tmp_path / "m.json"),
        "--limit",
        "48",
        "--latency-runs",
        "2",
        "--recovery",
        "0",
    ]
    assert main(args) == 0
    alone = sum(calls)
    save_head(run / HEAD_NAME, head)
    calls.clear()
    assert main(args) == 0
    assert sum(calls) == alone  # 48 samples and the timed sketches
    r = json.loads((tmp_path / "m.json").read_text())
    assert r["structured"] == evaluate_head(stroke_data, run / HEAD_NAME, run, limit=48)["head"]


def test_several_data_sets_train_one_head_on_their_union(stroke_data, tmp_path, capsys):
    other = tmp_path / "curved-toy"  # a second set: the first shard of the first
    other.mkdir()
    for name in ("shard-00000.npz", "shard-00000.json"):
        shutil.copy(stroke_data / name, other / name)
    manifest = json.loads((stroke_data / "manifest.json").read_text())
    (other / "manifest.json").write_text(
        json.dumps({**manifest, "count": 32, "seed": 7, "shards": ["shard-00000.npz"]})
    )
    code = main(
        [
            "train-head",
            "--data",
            str(stroke_data),
            str(other),
            "--out",
            str(tmp_path / "run"),
            "--weights",
            str(stroke_data / "unet.pt"),
            "--epochs",
            "1",
            "--width",
            "16",
            "--layers",
            "1",
            "--count",
            "40",
        ]
    )
    assert code == 0
    _, ckpt = load_head(tmp_path / "run" / HEAD_NAME)
    assert ckpt["train_samples"] == 40 + 32  # the first 40 of one, all 32 of the other
    assert ckpt["data_counts"] == {str(stroke_data): 40, str(other): 32}
    for d in (stroke_data, other):  # one token cache per set
        assert (tmp_path / "run" / "tokens" / d.name / "tokens-00000.pt").exists()
    # the union's items are each set's, in order
    from Sketch2CADWorkbench.inference.weights import load_model
    from training.heads import training_items

    model, _ = load_model(stroke_data / "unet.pt")
    items, _ = training_items([stroke_data, other], model, tmp_path / "run" / "tokens", 40)
    alone = extract(other, model)
    assert len(items) == 72 and [it.op for it in items[40:]] == [it.op for it in alone[:32]]


def test_two_training_sets_of_one_name_are_refused(stroke_data, tmp_path, capsys):
    twin = tmp_path / "x" / stroke_data.name
    shutil.copytree(stroke_data, twin)
    assert (
        main(
            [
                "train-head",
                "--data",
                str(stroke_data),
                str(twin),
                "--out",
                str(tmp_path / "run"),
                "--weights",
                str(stroke_data / "unet.pt"),
                "--epochs",
                "1",
            ]
        )
        == 2
    )
    assert "distinct folder names" in capsys.readouterr().err


def test_a_head_of_fewer_classes_starts_a_grown_one_with_what_it_learnt(tmp_path):
    from training.heads import warm_start

    cfg = HeadConfig(channels=12, width=16, layers=1)
    torch.manual_seed(0)
    trained = StructureHead(cfg).state_dict()
    # the head of four classes an earlier version trained: its output layers lack the
    # shell's rows (the class logit, the face logit and the last two role logits)
    grown = {"cls_out", "face_out"}
    earlier = {
        k: v[:4] if k.split(".")[0] in grown else v[:10] if k.startswith("role_out") else v
        for k, v in trained.items()
    }
    torch.save({"model": earlier}, tmp_path / "earlier.pt")
    torch.manual_seed(1)
    head = StructureHead(cfg)
    fresh = {k: v.clone() for k, v in head.state_dict().items()}
    warm_start(head, tmp_path / "earlier.pt")
    now = head.state_dict()
    for k, v in earlier.items():
        assert torch.equal(now[k][: len(v)], v), k
    assert torch.equal(now["cls_out.weight"][4:], fresh["cls_out.weight"][4:])
    assert torch.equal(now["role_out.bias"][10:], fresh["role_out.bias"][10:])
    with pytest.raises(ValueError, match="does not fit"):
        warm_start(
            StructureHead(HeadConfig(channels=12, width=8, layers=1)), tmp_path / "earlier.pt"
        )
