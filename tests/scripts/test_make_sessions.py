# SPDX-License-Identifier: LGPL-2.1-or-later
"""scripts/make_sessions.py: the example sessions are read as their designer would have the
workbench set, regularization on with the grid their protocol was designed on."""

import json
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_protocol_with_half_millimetres_was_designed_on_a_half_millimetre_grid(load_file):
    grid = load_file("scripts/make_sessions").designer_grid
    assert grid('{"size": [80.0, 20.0, 20.0], "r0": 6.5}') == 0.5
    # control points at thirds of a length are on no grid and say nothing of it
    assert grid('{"size": [80.0, 20.0, 20.0], "profile": [[6.0, 0.0], [5.6667, 30.6667]]}') == 1.0


def test_every_example_session_step_reads_with_regularization_on_its_designers_grid(load_file):
    grid = load_file("scripts/make_sessions").designer_grid
    sessions = sorted((EXAMPLES / "sessions").glob("*.json"))
    assert sessions
    for path in sessions:
        want = grid((EXAMPLES / "protocols" / path.name).read_text())
        for step in json.loads(path.read_text())["steps"]:
            assert step["choices"]["regularize"] is True, path.name
            assert step["choices"].get("snap_step") == want, path.name
