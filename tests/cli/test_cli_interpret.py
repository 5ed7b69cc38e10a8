# SPDX-License-Identifier: LGPL-2.1-or-later
"""`sketch2cad interpret` never writes over the session it reads (the user's sketches), and
replays each step with the choices saved in it."""

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

CLI = [sys.executable, "-m", "Sketch2CADWorkbench.cli"]
SESSION = Path(__file__).resolve().parents[2] / "examples" / "sessions" / "camera.json"


def test_an_output_on_the_session_is_refused_and_the_session_kept(tmp_path):
    s = tmp_path / "s.json"
    shutil.copy(SESSION, s)
    before = s.read_bytes()
    for option in ("--protocol", "--step", "--png"):
        out = subprocess.run(
            [*CLI, "interpret", str(s), option, str(s)], capture_output=True, text=True, timeout=120
        )
        assert out.returncode == 2 and "same file as SESSION" in out.stderr, out.stderr
        assert s.read_bytes() == before
    out = subprocess.run(
        [
            *CLI,
            "interpret",
            str(s),
            "--protocol",
            str(tmp_path / "x"),
            "--step",
            str(tmp_path / "x"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "--step" in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]


def test_the_replay_keeps_the_snaps_a_step_undid_undone_and_its_grid(tmp_path):
    # hammer's first step (a sweep) snaps its position to the face's centre line; the
    # Sketch panel's "Undo snap" saves skip_snaps in the step, and a replay honours it
    session = json.loads(SESSION.with_name("hammer.json").read_text())
    session["steps"] = session["steps"][:1]
    choices = session["steps"][0]["choices"]
    choices.update(regularize=True, snap_step=1.0)
    outputs = []
    for skip in ([], ["position"]):
        choices["skip_snaps"] = skip
        (tmp_path / "s.json").write_text(json.dumps(session))
        out = subprocess.run(
            [*CLI, "interpret", str(tmp_path / "s.json")],
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert out.returncode == 0, out.stderr
        outputs.append(out.stdout)
    assert "position snapped" in outputs[0] and "position snapped" not in outputs[1]
    assert all("snapped to the 1 mm grid" in o for o in outputs)


def test_each_step_is_read_on_the_compared_models_own_step(tmp_path):
    # lamp's plate and post; the plate's strokes are a scribble that reads as nothing, so
    # the post, read after it on the box, misses the plate, and read alone on the
    # protocol's plate is found
    examples = SESSION.parents[1]
    session = json.loads((examples / "sessions" / "lamp.json").read_text())
    protocol = json.loads((examples / "protocols" / "lamp.json").read_text())
    session["steps"] = session["steps"][:2]
    session["steps"][0]["strokes"] = [[[10.0, 10.0], [11.0, 10.0]]]
    protocol["operations"] = protocol["operations"][:2]
    (tmp_path / "s.json").write_text(json.dumps(session))
    (tmp_path / "p.json").write_text(json.dumps(protocol))
    base = [
        *CLI,
        "interpret",
        str(tmp_path / "s.json"),
        "--compare",
        str(tmp_path / "p.json"),
        "--keep-going",
        "--regularize",
        "off",
    ]
    ious, ends = {}, {}
    for extra in ([], ["--each-step"]):
        out = subprocess.run(base + extra, capture_output=True, text=True, timeout=600)
        assert out.returncode == 0, out.stderr
        lines = [
            re.search(
                r"after step \d( \(this step alone\))?: ([0-9.]+)(; the session "
                r"so, every other step exact: ([0-9.]+))?$",
                line,
            )
            for line in out.stdout.splitlines()
            if "volume IoU" in line
        ]
        assert all(lines) and all(bool(m[1]) == bool(extra) for m in lines)
        ious[bool(extra)] = [float(m[2]) for m in lines]
        ends[bool(extra)] = [m[4] and float(m[4]) for m in lines]
    assert ious[True][1] > 0.95 > ious[False][1]
    # where the session ends with a step so read: none for the step not read, and for
    # the last step where that step alone ends
    assert ends[False] == [None, None] and ends[True][0] is None
    assert ends[True][1] == ious[True][1]
    out = subprocess.run(
        [*CLI, "interpret", str(tmp_path / "s.json"), "--each-step"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "--each-step needs --compare" in out.stderr


def test_a_session_without_steps_is_refused_and_nothing_written(tmp_path):
    s = json.loads(SESSION.read_text())
    s["steps"] = []
    (tmp_path / "s.json").write_text(json.dumps(s))
    out = subprocess.run(
        [*CLI, "interpret", str(tmp_path / "s.json"), "--step", str(tmp_path / "x.step")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "has no sketched steps" in out.stderr, out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]


def test_a_doubtful_step_stops_the_run_unless_accepted_or_skipped(tmp_path, monkeypatch, capsys):
    from Sketch2CADWorkbench.cli import main
    from Sketch2CADWorkbench.inference import reading

    s = json.loads(SESSION.read_text())
    s["steps"] = s["steps"][:1]
    (tmp_path / "s.json").write_text(json.dumps(s))
    monkeypatch.setattr(reading, "DOUBT", {"sketch_off_px": -1.0})  # every reading doubtful
    step = tmp_path / "out.step"
    args = ["interpret", str(tmp_path / "s.json"), "--step", str(step)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "step 1: doubtful, not added: the strokes do not look much like" in err
    assert "--accept-doubtful adds" in err and not step.exists()
    assert main([*args, "--keep-going"]) == 0
    assert "0 of 1 steps interpreted" in capsys.readouterr().out
    assert main([*args, "--accept-doubtful"]) == 0
    out = capsys.readouterr().out
    assert "1 of 1 steps interpreted" in out and "(warning: the strokes do not look" in out


def test_interpreting_shows_its_progress_on_a_terminal_below_the_steps_it_prints(
    tmp_path, stderr_of, capsys
):
    from Sketch2CADWorkbench.cli import main

    s = json.loads(SESSION.read_text())
    s["steps"] = s["steps"][:2]
    (tmp_path / "s.json").write_text(json.dumps(s))
    err = stderr_of(True)
    assert main(["interpret", str(tmp_path / "s.json"), "--accept-doubtful"]) == 0
    assert "interpret s.json" in err.getvalue() and "/2 [" in err.getvalue(), err.getvalue()
    out = capsys.readouterr().out
    assert "step 1: " in out and "step 2: " in out and "2 of 2 steps interpreted" in out
