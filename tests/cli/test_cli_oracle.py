# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad oracle`: a line per session and per step, the figures in JSON, and
clear refusals of files that are not there or do not belong together."""

import json

import pytest
from session_fixtures import BASE, BOSS, POST, sketched_step

from Sketch2CADWorkbench.brep.protocol import Protocol
from Sketch2CADWorkbench.cli import main
from Sketch2CADWorkbench.inference.session import Session


@pytest.fixture
def files(tmp_path):
    protocol = Protocol(BASE, [POST, BOSS])
    protocol.save(tmp_path / "post.protocol.json")
    Session(BASE, [sketched_step(protocol, k, sigma=3.0, seed=k) for k in range(2)]).save(
        tmp_path / "post.json"
    )
    return tmp_path / "post.json", tmp_path / "post.protocol.json"


def test_each_step_and_the_end_are_printed_and_written(files, tmp_path, capsys):
    out = tmp_path / "oracle.json"
    assert main(["oracle", *map(str, files), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("post: oracle's final volume IoU 0.")
    assert "  step 1: alone 0." in text and "  step 2: alone 0." in text
    figures = json.loads(out.read_text())["post"]
    assert len(figures["steps"]) == 2 and 0.5 < figures["final_iou"] < 1.0
    assert figures["steps"][0]["strokes"] == 12
    k = figures["weakest_step"]
    assert f"step {k} alone ends it at {figures['weakest_session_iou']:.3f} at best" in text
    assert figures["weakest_session_iou"] == max(
        figures["steps"][k - 1]["session_iou"], figures["steps"][k - 1]["snapped_session_iou"]
    )


def test_a_missing_file_and_a_protocol_of_another_length_are_named(files, tmp_path, capsys):
    assert main(["oracle", str(files[0]), str(tmp_path / "missing.json")]) == 2
    assert "missing.json" in capsys.readouterr().err
    Protocol(BASE, [POST]).save(tmp_path / "short.json")
    assert main(["oracle", str(files[0]), str(tmp_path / "short.json")]) == 2
    assert "2 steps and the protocol 1 operations" in capsys.readouterr().err


def test_a_session_without_its_protocol_is_refused(files, capsys):
    assert main(["oracle", str(files[0])]) == 2
    assert "give a session and its protocol, or --examples" in capsys.readouterr().err
