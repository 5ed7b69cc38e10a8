# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad extrusion-bound`: one line per set, a pooled line over several, the shells'
bound with --shells, and a clear refusal of a folder that is not a generated set."""

import json
from pathlib import Path

import pytest

import training.extrusion_bound
import training.shell_bound
from Sketch2CADWorkbench.cli import main


@pytest.fixture(autouse=True)
def figures(monkeypatch):
    figures = {"a": (10, 0.9, 0.9, 0.95), "b": (30, 0.5, 0.6, 0.7), "none": (0, None, None, None)}

    def bound_of_set(data, limit):
        n, ml, best, bound = figures[Path(data).name]
        return {"n": n, "oracle_ml_rate": ml, "best_decision_rate": best, "expected_bound": bound}

    monkeypatch.setattr(training.extrusion_bound, "bound_of_set", bound_of_set)
    monkeypatch.setattr(
        training.shell_bound, "bound_of_set", lambda data, limit: bound_of_set(data, limit)
    )


def test_several_sets_print_a_line_each_and_pool_by_their_counts(tmp_path, capsys):
    for name in ("a", "b", "none"):
        (tmp_path / name).mkdir()
    out = tmp_path / "bound.json"
    sets = [str(tmp_path / n) for n in ("a", "b", "none")]
    assert main(["extrusion-bound", *sets, "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "a: 10 extrusions; oracle least squares 90.0%" in text
    assert "none: no extrusion on a planar face" in text
    pooled = json.loads(out.read_text())["pooled"]
    assert pooled["n"] == 40
    assert pooled["expected_bound"] == pytest.approx((10 * 0.95 + 30 * 0.7) / 40)


def test_the_shells_bound_is_printed_with_shells(tmp_path, capsys):
    for name in ("a", "none"):
        (tmp_path / name).mkdir()
    assert main(["extrusion-bound", str(tmp_path / "a"), str(tmp_path / "none"), "--shells"]) == 0
    text = capsys.readouterr().out
    assert "a: 10 shells; oracle least squares 90.0%" in text
    assert "none: no shell with a rim of lines" in text


def test_a_folder_that_is_not_there_is_named(tmp_path, capsys):
    (tmp_path / "a").mkdir()
    assert main(["extrusion-bound", str(tmp_path / "a"), str(tmp_path / "missing")]) == 2
    captured = capsys.readouterr()
    assert "missing: no such generated set" in captured.err
    assert captured.out == ""
