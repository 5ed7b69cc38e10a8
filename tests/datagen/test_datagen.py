# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic data: valid sequences, correct labels, determinism, resumability."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import apply_operation, replay
from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.datagen.curves import operation_curves
from Sketch2CADWorkbench.datagen.dataset import Dataset
from Sketch2CADWorkbench.datagen.generate import PER_CONTEXT, generate_block
from Sketch2CADWorkbench.datagen.sample import (BEVEL_L, END, EXTRUDE_OFFSET, PROFILE, START)
from Sketch2CADWorkbench.datagen.sequences import sample_sequence
from Sketch2CADWorkbench.datagen.strokes import noise_sigma, perturb
from Sketch2CADWorkbench.render.maps import MapRenderer
from Sketch2CADWorkbench.render.visibility import visible_fraction

CLI = str(Path(__file__).resolve().parents[2] / ".venv" / "bin" / "sketch2cad")


@pytest.fixture(scope="module")
def renderer():
    return MapRenderer()


@pytest.fixture(scope="module")
def blocks(renderer):
    """Two blocks of noise-free-ish samples (level 1), one of each context length 1 and 2."""
    return generate_block(5, 0, 1, renderer) + generate_block(5, 1, 1, renderer)


@pytest.mark.parametrize("seed", range(6))
def test_sampled_protocols_replay_to_valid_solids(seed):
    rng = np.random.default_rng(seed)
    seq = sample_sequence(rng, 1 + seed % 4)
    solids = replay(seq.protocol)
    assert all(len(s.Solids()) == 1 and s.isValid() for s in solids)
    assert [round(s.Volume(), 6) for s in solids] == [round(s.Volume(), 6) for s in seq.solids]


def test_sample_labels_lie_on_the_projected_curves(blocks):
    """Stroke pixels of each label are near the projection of that label's 3D curves."""
    for s in blocks:
        context = replay(s.context)[-1]
        curves = operation_curves(context, s.operation, s.camera)
        for label in set(s.stroke_parts):
            proj = np.concatenate([s.camera.project(c.points)[0] for c in curves if c.label == label])
            jj, ii = np.nonzero((s.stroke_mask > 0) & (s.curve_label == label))
            if len(ii) == 0:
                continue  # overdrawn by another stroke
            px = np.stack([ii + 0.5, jj + 0.5], axis=1)
            dense = np.concatenate([np.linspace(a, b, 20) for c in curves if c.label == label
                                    for a, b in zip(s.camera.project(c.points)[0][:-1],
                                                    s.camera.project(c.points)[0][1:])])
            near = np.min(np.linalg.norm(px[:, None] - dense[None], axis=2), axis=1)
            # level-1 noise: endpoint RMS 1.4% of the diagonal (5 px); allow 4 sigma
            assert np.median(near) < 4 * noise_sigma(1, 256, 256), (s.op_type, label)
            assert len(proj)


def test_label_encodings_follow_the_paper(blocks):
    for s in blocks:
        parts = set(s.stroke_parts)
        if s.op_type is OperatorType.EXTRUDE:
            assert parts == {0, EXTRUDE_OFFSET}
        elif s.op_type is OperatorType.BEVEL:
            assert parts == {0, BEVEL_L}
        else:
            assert parts == {START, PROFILE, END}
        assert set(np.unique(s.curve_label[s.stroke_mask > 0])) <= parts
        assert np.all(s.curve_label[s.stroke_mask == 0] == 0)


def test_face_label_is_the_base_face_seen_in_the_context(blocks):
    for s in blocks:
        assert s.face_label.sum() > 0
        ids = np.unique(s.face_id[s.face_label > 0])
        assert len(ids) == 1
        context = replay(s.context)[-1]
        face = context.Faces()[int(ids[0])]
        assert np.dot(face.normalAt().toTuple(), s.operation.face.normal) > 0.999


def test_the_relevant_curve_is_mostly_visible(blocks, renderer):
    for s in blocks:
        context = replay(s.context)[-1]
        seen_on = apply_operation(context, s.operation) if s.op_type is OperatorType.EXTRUDE \
            else context
        curves = operation_curves(context, s.operation, s.camera)
        base = np.concatenate([c.points for c in curves if c.base])
        maps = renderer.render(seen_on, s.camera)
        assert visible_fraction(base, s.camera, maps, 2 * s.camera.pixel_size) >= 0.8


def test_generation_is_deterministic(renderer, blocks):
    again = generate_block(5, 0, 1, renderer)
    for a, b in zip(again, blocks[:PER_CONTEXT]):
        assert a.operation == b.operation and np.array_equal(a.sketch, b.sketch)
        assert np.array_equal(a.depth, b.depth)


def test_noise_levels_scale_the_stroke_perturbation():
    line = np.array([[20.0, 20.0], [200.0, 60.0]])
    spread = []
    for level in (1, 2, 3):
        rng = np.random.default_rng(0)
        d = [np.linalg.norm(perturb(line, rng, noise_sigma(level, 256, 256))[0] - line[0])
             for _ in range(300)]
        spread.append(np.sqrt(np.mean(np.square(d))))
    assert spread[0] < spread[1] < spread[2]
    # the RMS end-point displacement is the stated share of the image diagonal
    assert spread[0] == pytest.approx(0.014 * np.hypot(256, 256), rel=0.2)


def _run(*args):
    return subprocess.run([CLI, "datagen", *map(str, args)], capture_output=True, text=True,
                          timeout=600)


def test_datagen_is_the_same_with_any_worker_count_and_resumes(tmp_path):
    one, two = tmp_path / "one", tmp_path / "two"
    args = ("--count", 20, "--seed", 3, "--shard-size", 8)
    assert _run("--out", one, *args, "--workers", 1).returncode == 0
    assert _run("--out", two, *args, "--workers", 2).returncode == 0
    a, b = Dataset(one), Dataset(two)
    assert len(a) == len(b) == 20 and a.shards == [0, 1, 2]
    for k in a.shards:
        for name in ("sketch", "depth", "face_label", "curve_label", "op_type"):
            assert np.array_equal(a.arrays(k)[name], b.arrays(k)[name])
    # an interrupted run: one shard missing; a rerun makes exactly it again
    kept = (two / "shard-00000.npz").read_bytes()
    (two / "shard-00001.npz").unlink()
    (two / "shard-00001.json").unlink()
    out = _run("--out", two, *args, "--workers", 1, "--preview", tmp_path / "p.png")
    assert out.returncode == 0 and "8 samples in" in out.stdout
    assert (two / "shard-00000.npz").read_bytes() == kept
    c = Dataset(two)
    assert np.array_equal(c.arrays(1)["sketch"], a.arrays(1)["sketch"])
    assert (tmp_path / "p.png").stat().st_size > 10_000


def test_datagen_refuses_to_mix_data_sets(tmp_path):
    assert _run("--out", tmp_path, "--count", 4, "--seed", 1, "--workers", 1).returncode == 0
    out = _run("--out", tmp_path, "--count", 4, "--seed", 2, "--workers", 1)
    assert out.returncode == 2 and "holds a different data set" in out.stderr


def test_reader_returns_what_was_written(tmp_path, blocks):
    from Sketch2CADWorkbench.datagen.dataset import write_shard
    import json
    write_shard(tmp_path, 0, blocks)
    (tmp_path / "manifest.json").write_text(json.dumps(
        {"format": "sketch2cad-dataset", "version": 1, "count": len(blocks), "shard_size": 128,
         "shards": ["shard-00000.npz"]}))
    back = Dataset(tmp_path).samples(0)
    for a, b in zip(back, blocks):
        assert a.operation == b.operation and a.context == b.context and a.camera == b.camera
        assert np.array_equal(a.sketch, b.sketch) and np.array_equal(a.curve_label, b.curve_label)
        assert np.allclose(a.depth, b.depth, atol=1 / 255) and np.allclose(a.normal, b.normal,
                                                                           atol=1 / 127)
        assert all(np.allclose(x, y, atol=1e-3) for x, y in zip(a.strokes, b.strokes))
