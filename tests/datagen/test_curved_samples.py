# SPDX-License-Identifier: LGPL-2.1-or-later
"""Samples on curved faces: the last operation stands on a cylinder's or cone's side
of its context, builds there, and its labels name that face and the stroke parts; the
bound that rejects candidates before their Booleans holds. A curved set takes the noise
levels in turns with "mix", is the same for the same seed, and resumes by shard."""

import numpy as np
import pytest

import datagen.curved
from datagen.curved import (
    change_bound_on_curved,
    curved_context,
    curved_sample,
    draw_kind,
    sample_on_curved,
)
from datagen.dataset import Dataset
from datagen.generate import sample_rng
from Sketch2CADWorkbench.brep.faces import OperationError, is_curved, model_scale
from Sketch2CADWorkbench.brep.operators import apply_operation, operation_result, replay
from Sketch2CADWorkbench.brep.protocol import Mode, OperatorType, straight_profile
from Sketch2CADWorkbench.cli import main


def test_a_curved_sample_stands_on_a_curved_face_of_its_context(renderer):
    s = curved_sample(sample_rng(5, 0), 1, renderer)  # a hole drilled into a cylinder
    assert s.operation.face.surface.curved
    context = replay(s.context)[-1]
    faces = context.Faces()
    labelled = np.unique(s.face_id[s.face_label > 0.5])
    assert len(labelled) == 1
    assert faces[int(labelled[0])].geomType() in ("CYLINDER", "CONE")
    assert set(s.stroke_parts) == {0, 1, 2}
    assert abs(apply_operation(context, s.operation).Volume() - context.Volume()) > 0


def test_the_cheap_bound_is_never_below_the_volume_change_a_candidate_makes():
    # it rejects candidates before their Booleans: one it underestimated would be lost
    rng = np.random.default_rng(3)
    checked = set()
    for _ in range(3):
        seq, faces = curved_context(rng)
        solid = seq.stages[-1].solid
        for _ in range(12):
            got = sample_on_curved(rng, faces[int(rng.integers(len(faces)))], draw_kind(rng))
            if got is None:
                continue
            op, f = got
            try:
                change = abs(operation_result(solid, op).volume - seq.stages[-1].volume)
            except OperationError:
                continue
            # up to the noise of OCCT's volumes of a large solid (~1e-5 of it), far
            # under the 1% a kept candidate changes
            noise = 1e-4 * seq.stages[-1].volume
            assert change <= change_bound_on_curved(op, f, model_scale(solid)) + noise
            checked.add(op.type)
    assert checked == {OperatorType.ADDSUB, OperatorType.SWEEP, OperatorType.EXTRUDE}


def test_a_curved_context_ends_in_an_added_cylinder_or_cone():
    for seed in range(3):
        seq, faces = curved_context(np.random.default_rng(seed))
        op = seq.protocol.operations[-1]
        assert op.type is OperatorType.SWEEP and op.mode is Mode.ADD
        assert np.allclose(op.profile, straight_profile(op.r0, op.r1, op.d))
        assert faces and all(is_curved(f) for f in faces)


def _curved(out, count, noise, seed=5) -> int:
    return main(
        [
            "datagen",
            "--curved",
            "--out",
            str(out),
            "--count",
            str(count),
            "--seed",
            str(seed),
            "--noise-level",
            noise,
        ]
    )


def _arrays(folder):
    ds = Dataset(folder)
    return [ds.shard_arrays(k) for k in ds.shards], [ds.shard_meta(k) for k in ds.shards]


@pytest.fixture(scope="module")
def mixed(tmp_path_factory):
    """A curved set of 4 samples with the noise levels mixed, in shards of 2."""
    out = tmp_path_factory.mktemp("mixed")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(datagen.curved, "SHARD_SIZE", 2)
        assert _curved(out, 4, "mix") == 0
    return out


def test_a_mixed_curved_set_takes_the_levels_in_turns(mixed):
    ds = Dataset(mixed)
    assert ds.manifest["noise"] == "mix" and ds.manifest["noise_levels"] == [1, 2, 3]
    assert ds.manifest["curved"] and len(ds) == 4 and ds.shards == [0, 1]
    levels = np.concatenate([a["noise_level"] for a in _arrays(mixed)[0]])
    assert levels.tolist() == [1, 2, 3, 1]


def test_a_mixed_set_draws_the_samples_of_its_seed_each_at_its_turns_level(mixed, tmp_path):
    # sample 0 takes level 1 in turn: it is sample 0 of the level-1 set of that seed
    assert _curved(tmp_path, 1, "1") == 0
    (one,), (one_meta,) = _arrays(tmp_path)
    first, first_meta = _arrays(mixed)[0][0], _arrays(mixed)[1][0]
    assert one_meta[0] == first_meta[0]
    for name in one:
        assert np.array_equal(one[name][0], first[name][0]), name


def test_a_curved_set_resumes_by_shard_with_the_same_bytes(mixed, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(datagen.curved, "SHARD_SIZE", 2)
    for f in mixed.iterdir():
        (tmp_path / f.name).write_bytes(f.read_bytes())
    (tmp_path / "shard-00001.json").unlink()  # stopped while writing shard 1
    kept = (tmp_path / "shard-00000.npz").stat().st_mtime_ns
    made = []
    real = datagen.curved.curved_sample

    def counted(rng, level, renderer):
        made.append(level)
        return real(rng, level, renderer)

    monkeypatch.setattr(datagen.curved, "curved_sample", counted)
    assert _curved(tmp_path, 4, "mix") == 0
    assert made == [3, 1]  # samples 2 and 3 only
    assert (tmp_path / "shard-00000.npz").stat().st_mtime_ns == kept
    for name in ("shard-00000.npz", "shard-00001.npz", "shard-00001.json", "manifest.json"):
        assert (tmp_path / name).read_bytes() == (mixed / name).read_bytes(), name
    assert _curved(tmp_path, 4, "mix", seed=6) == 2  # another set: refused
    assert "holds a different data set" in capsys.readouterr().err
