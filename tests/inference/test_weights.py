# SPDX-License-Identifier: LGPL-2.1-or-later
"""The predictor the interpret pipeline uses: weights from disk, one pass per sketch."""

import numpy as np
import pytest
import torch

from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference import weights
from Sketch2CADWorkbench.inference.models import Sketch2CADNet, save_checkpoint


def test_missing_weights_say_how_to_get_them(tmp_path):
    with pytest.raises(FileNotFoundError, match="sketch2cad train --data DIR --out RUN"):
        weights.load_predictor(tmp_path)


def test_the_default_weights_live_inside_the_package():
    assert weights.DEFAULT_WEIGHTS.parent.name == "weights"
    assert weights.DEFAULT_WEIGHTS.parent.parent == weights.Path(weights.__file__).parent


def test_the_predictor_classifies_and_segments_from_one_pass(tiny_config, tmp_path, monkeypatch):
    save_checkpoint(tmp_path / weights.WEIGHTS_NAME, Sketch2CADNet(tiny_config))
    predictor = weights.load_predictor(tmp_path)  # a run folder
    passes = []
    original = predictor.model.predict
    monkeypatch.setattr(predictor.model, "predict", lambda x: passes.append(1) or original(x))
    x = np.random.default_rng(0).random((5, 32, 32), dtype=np.float32)
    probs = predictor.classify(x)
    assert probs.shape == (4,) and np.isclose(probs.sum(), 1)
    f, c = predictor.segment(x, OperatorType.SWEEP)
    assert f.shape == c.shape == (32, 32) and len(passes) == 1
    _, _, c_all = original(torch.from_numpy(x)[None])
    assert np.array_equal(c, c_all[0, 3].numpy())
    predictor.segment(x.copy(), OperatorType.SWEEP)  # another sketch: another pass
    assert len(passes) == 2


def test_a_garbage_weights_file_is_a_clean_error_naming_it(tmp_path):
    from Sketch2CADWorkbench.inference.models import load_checkpoint

    bad = tmp_path / "bad.pt"
    bad.write_bytes(bytes(range(256)) * 10)
    with pytest.raises(ValueError, match=r"bad.pt: not a readable sketch2cad-net checkpoint"):
        load_checkpoint(bad)


def test_a_head_beside_the_weights_loads_with_them_and_only_for_that_unet(tiny_config, tmp_path):
    from Sketch2CADWorkbench.inference.head.checkpoint import save_head, sha256_of
    from Sketch2CADWorkbench.inference.head.model import HeadConfig, StructureHead
    from Sketch2CADWorkbench.inference.head.predictor import StructuredPredictor
    from Sketch2CADWorkbench.inference.head.tokens import feature_channels

    net = Sketch2CADNet(tiny_config)
    unet = tmp_path / weights.WEIGHTS_NAME
    save_checkpoint(unet, net)
    assert type(weights.load_predictor(tmp_path)) is weights.NetworkPredictor
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    save_head(tmp_path / weights.HEAD_NAME, head, unet_sha256=sha256_of(unet))
    assert isinstance(weights.load_predictor(tmp_path), StructuredPredictor)
    assert type(weights.load_predictor(unet, structured=False)) is weights.NetworkPredictor
    torch.manual_seed(1)
    save_checkpoint(unet, Sketch2CADNet(tiny_config))  # the U-Net retrained, the head not
    with pytest.raises(ValueError, match="another U-Net"):
        weights.load_predictor(tmp_path)
    save_head(tmp_path / weights.HEAD_NAME, head)  # a head that names no U-Net
    with pytest.raises(ValueError, match="another U-Net"):
        weights.load_predictor(tmp_path)
