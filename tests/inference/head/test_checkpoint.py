# SPDX-License-Identifier: LGPL-2.1-or-later
"""A head's checkpoint: saved, loaded back, refused beside another U-Net."""

import pytest
import torch

from Sketch2CADWorkbench.inference.head.checkpoint import load_head, save_head
from Sketch2CADWorkbench.inference.head.model import HeadConfig, StructureHead
from Sketch2CADWorkbench.inference.head.predictor import load_structured_predictor
from Sketch2CADWorkbench.inference.head.tokens import feature_channels
from Sketch2CADWorkbench.inference.models import save_checkpoint


def test_a_head_loads_back_and_refuses_another_unets_features(net, tiny_config, tmp_path):
    head = StructureHead(HeadConfig(channels=feature_channels(net), width=16, layers=1))
    unet = tmp_path / "unet.pt"
    save_checkpoint(unet, net)
    save_head(tmp_path / "head.pt", head, unet_sha256="0" * 64)
    loaded, _ = load_head(tmp_path / "head.pt")
    for a, b in zip(head.state_dict().values(), loaded.state_dict().values(), strict=True):
        assert torch.equal(a, b)
    with pytest.raises(ValueError, match="another U-Net"):
        load_structured_predictor(tmp_path / "head.pt", unet)
    (tmp_path / "junk.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="sketch2cad-head"):
        load_head(tmp_path / "junk.pt")
