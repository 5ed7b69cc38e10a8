# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad head-recovery`: the U-Net and head rows run apart and print together, the
U-Net row with the U-Net alone even where a head lies beside it."""

import json

import pytest

from Sketch2CADWorkbench.cli import head_recovery, main


@pytest.fixture
def seen(monkeypatch):
    calls = []

    def plain(weights, structured=True):
        calls.append(("unet", structured))
        return "unet predictor"

    def structured(head, weights):
        calls.append(("head", head.name))
        return "head predictor"

    def recovery(data, predictor, limit):
        rate = 0.9 if predictor == "unet predictor" else 0.95
        per = {
            op: {"recovery_rate": rate, "recovery_rate_with_flip": 1.0, "recovery_n": 10}
            for op in ("extrude", "bevel", "addsub", "sweep")
        }
        return {"per_operator": per, "interpret_median_ms": 100.0, "failure_reasons": {}}

    monkeypatch.setattr(head_recovery, "load_predictor", plain)
    monkeypatch.setattr(head_recovery, "load_structured_predictor", structured)
    monkeypatch.setattr(head_recovery, "recovery", recovery)
    return calls


def test_rows_run_apart_print_together(seen, tmp_path, capsys):
    out = tmp_path / "rows.json"
    (tmp_path / "run").mkdir()
    for rows in (["unet"], ["head"]):
        args = ["--data", "d", "--head", str(tmp_path / "run"), "--rows", *rows]
        assert main(["head-recovery", *args, "--json", str(out)]) == 0
    assert seen == [("unet", False), ("head", "sketch2cad_head.pt")]
    assert set(json.loads(out.read_text())) == {"unet", "head"}
    printed = capsys.readouterr().out.splitlines()
    assert any(ln.startswith("unet       90.0 /") for ln in printed)
    assert any(ln.startswith("head       95.0 /") for ln in printed)


def test_the_head_row_needs_a_head(seen, capsys):
    assert main(["head-recovery", "--data", "d", "--rows", "head"]) == 2
    assert "the head row needs --head" in capsys.readouterr().err
    assert seen == []
