# SPDX-License-Identifier: LGPL-2.1-or-later
"""scripts/recovery_with_head.py: the U-Net and head rows run apart and print together,
the U-Net row with the U-Net alone even where a head lies beside it."""

import json
import sys

import pytest


@pytest.fixture
def script(monkeypatch, load_script):
    module = load_script("recovery_with_head")
    seen = []

    def plain(weights, structured=True):
        seen.append(("unet", structured))
        return "unet predictor"

    def structured(head, weights):
        seen.append(("head", head.name))
        return "head predictor"

    def recovery(data, predictor, limit):
        rate = 0.9 if predictor == "unet predictor" else 0.95
        per = {
            op: {"recovery_rate": rate, "recovery_rate_with_flip": 1.0, "recovery_n": 10}
            for op in ("extrude", "bevel", "addsub", "sweep")
        }
        return {"per_operator": per, "interpret_median_ms": 100.0, "failure_reasons": {}}

    monkeypatch.setattr(module, "load_predictor", plain)
    monkeypatch.setattr(module, "load_structured_predictor", structured)
    monkeypatch.setattr(module, "recovery", recovery)
    return module, seen


def test_rows_run_apart_print_together(script, tmp_path, monkeypatch, capsys):
    module, seen = script
    out = tmp_path / "rows.json"
    (tmp_path / "run").mkdir()
    for rows in (["unet"], ["head"]):
        monkeypatch.setattr(
            sys,
            "argv",
            [
                "x",
                "--data",
                "d",
                "--head",
                str(tmp_path / "run"),
                "--rows",
                *rows,
                "--json",
                str(out),
            ],
        )
        assert module.main() == 0
    assert seen == [("unet", False), ("head", "sketch2cad_head.pt")]
    assert set(json.loads(out.read_text())) == {"unet", "head"}
    printed = capsys.readouterr().out.splitlines()
    assert any(ln.startswith("unet       90.0 /") for ln in printed)
    assert any(ln.startswith("head       95.0 /") for ln in printed)


def test_the_head_row_needs_a_head(script, monkeypatch):
    module, _ = script
    monkeypatch.setattr(sys, "argv", ["x", "--data", "d", "--rows", "head"])
    with pytest.raises(SystemExit):
        module.main()
