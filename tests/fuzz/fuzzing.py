# SPDX-License-Identifier: LGPL-2.1-or-later
"""The project's own fuzzing: malformed protocols and sessions, random strokes over random
models, writers killed midway, concurrent writers. Each campaign returns a Tally of what
happened; tests/fuzz/test_fuzz.py runs small seeded campaigns, `python tests/fuzz/run.py`
the full ones with their counts.

Outcomes: "accepted" (a valid input, or a reading), "flagged" (a reading said to be
doubtful: its own sketch lies far from the strokes, or the networks all but rule out its
operator), "clean" (the error the API documents:
ProtocolError, SessionError, OperationError, InterpretError, a ValueError with a
message), "crash" (anything else: a traceback), "invalid" (an accepted result that is
not one valid solid), "changed" (the caller's solid changed), "broken" (a reader saw a
partial file), "leftover" (temporaries a later write did not clean).
"""

from __future__ import annotations

import copy
import json
import random
import resource
import subprocess
import sys
import tempfile
import textwrap
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from Sketch2CADWorkbench.brep.exchange import to_brep_text
from Sketch2CADWorkbench.brep.faces import OperationError
from Sketch2CADWorkbench.brep.files import MARK
from Sketch2CADWorkbench.brep.operators import build, make_box
from Sketch2CADWorkbench.brep.protocol import ProtocolError, loads
from Sketch2CADWorkbench.inference.session import SessionError, load_session

ROOT = Path(__file__).resolve().parents[2]
CLEAN = (ProtocolError, SessionError, OperationError, ValueError)
# What a hostile file puts where a value belongs.
NASTY = [
    None,
    True,
    False,
    "x",
    "",
    [],
    {},
    [[]],
    -1,
    0,
    1,
    -1e300,
    1e300,
    1e-300,
    1e-12,
    10**400,
    2**63,
    [0, 0, 0],
    [1e300, 1e300, 0],
    [0, 0, -1],
    {"type": "box"},
    ["addsub"],
    "NaN",
]


@dataclass
class Tally:
    counts: Counter = field(default_factory=Counter)
    worst_s: float = 0.0
    worst_case: str = ""
    crashes: list = field(default_factory=list)

    def add(self, outcome: str, seconds: float = 0.0, case: str = "") -> None:
        self.counts[outcome] += 1
        if seconds > self.worst_s:
            self.worst_s, self.worst_case = seconds, case
        if outcome == "crash" and len(self.crashes) < 5:
            self.crashes.append(case)

    def line(self, name: str) -> str:
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        return (
            f"{name}: "
            + ", ".join(f"{k} {v}" for k, v in sorted(self.counts.items()))
            + f"; worst {self.worst_s:.2f} s ({self.worst_case[:60]}); peak RSS "
            f"{peak:.0f} MB"
        )


def _leaves(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _leaves(v, path + (i,))
    yield path


def mutate(doc: dict, rng: random.Random) -> str:
    """A malformed variant of a JSON document, as text: a value replaced by a nasty one,
    a key dropped or added, the text cut or nested deep."""
    kind = rng.random()
    if kind < 0.05:
        return "[" * rng.choice([10, 1000, 100000]) + "]" * 3
    text_cut = json.dumps(doc)
    if kind < 0.1:
        return text_cut[: rng.randrange(len(text_cut))]
    bad = copy.deepcopy(doc)
    paths = [p for p in _leaves(bad) if p]
    path = rng.choice(paths)
    parent = bad
    for k in path[:-1]:
        parent = parent[k]
    if kind < 0.2 and isinstance(parent, dict):
        del parent[path[-1]]
    elif kind < 0.25 and isinstance(parent, dict):
        parent["unexpected"] = rng.choice(NASTY)
    else:
        parent[path[-1]] = rng.choice(NASTY)
    text = json.dumps(bad)
    return text.replace('"NaN"', "NaN") if rng.random() < 0.5 else text


def _classify(fn, case: str) -> tuple[str, float, str]:
    t = time.perf_counter()
    try:
        fn()
        outcome = "accepted"
    except CLEAN as e:
        outcome = "clean" if str(e) else "crash"
    except Exception as e:
        outcome = "crash"
        case = f"{case}: {type(e).__name__}: {e}"[:300]
    return outcome, time.perf_counter() - t, case


def _mutated(examples: str, n: int, seed: int, read) -> Tally:
    """n mutations of the examples/<examples> files, each given to read(text, i)."""
    rng, tally = random.Random(seed), Tally()
    docs = [
        json.loads(p.read_text()) for p in sorted((ROOT / "examples" / examples).glob("*.json"))
    ]
    for i in range(n):
        text = mutate(rng.choice(docs), rng)
        tally.add(*_classify(lambda text=text, i=i: read(text, i), f"{examples} {i}"))
    return tally


def malformed_protocols(n: int, seed: int) -> Tally:
    """n mutations of the example protocols, loaded and built."""
    return _mutated("protocols", n, seed, lambda text, i: build(loads(text, f"case {i}")))


def malformed_sessions(n: int, seed: int) -> Tally:
    """n mutations of the example sessions, read as files (load_session)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "session.json"

        def read(text: str, i: int) -> None:
            path.write_text(text)
            load_session(path)

        return _mutated("sessions", n, seed, read)


def random_strokes(n: int, seed: int, predictor=None) -> Tally:
    """n random stroke sets (scribbles, dots, lines, many short strokes) over random boxes
    from random views, through the whole interpret pipeline."""
    from datagen.sequences import random_box
    from datagen.views import view_direction
    from Sketch2CADWorkbench.inference.context import InterpretError
    from Sketch2CADWorkbench.inference.interpret import interpret
    from Sketch2CADWorkbench.inference.weights import load_predictor
    from Sketch2CADWorkbench.render.frustum import fit_camera
    from Sketch2CADWorkbench.render.maps import MapRenderer

    predictor = predictor or load_predictor()
    renderer, rng, tally = MapRenderer(), np.random.default_rng(seed), Tally()
    for i in range(n):
        solid = make_box(random_box(rng))
        cam = fit_camera(solid, view_direction(rng, np.array([0.0, 0.0, 1.0])))
        k = int(rng.choice([1, 2, 4, 8, 30]))
        strokes = [
            np.cumsum(
                rng.normal(0, rng.choice([0.0, 3.0, 20.0]), (int(rng.integers(2, 40)), 2)), axis=0
            )
            + rng.uniform(0, 256, 2)
            for _ in range(k)
        ]
        before = to_brep_text(solid)
        t = time.perf_counter()
        try:
            got = interpret(solid, strokes, cam, predictor, renderer)
            outcome = (
                "invalid" if not got.solid.isValid() else "flagged" if got.doubtful else "accepted"
            )
        except (InterpretError, OperationError) as e:
            outcome = "clean" if str(e) else "crash"
        except Exception as e:
            outcome = "crash"
            tally.crashes.append(f"strokes {i}: {type(e).__name__}: {e}"[:300])
        if to_brep_text(solid) != before:
            tally.add("changed")
        tally.add(outcome, time.perf_counter() - t, f"strokes {i} ({k} strokes)")
    return tally


WRITER = textwrap.dedent("""
    import sys
    from Sketch2CADWorkbench.brep.protocol import load
    p = load(sys.argv[1])
    while True:
        p.save(sys.argv[2])
""")


def killed_writers(n: int, seed: int) -> Tally:
    """n writers of one protocol file killed (SIGKILL) at random moments; after each,
    the file must be the whole protocol, and the next write must clean the temporary."""
    rng, tally = random.Random(seed), Tally()
    src = ROOT / "examples" / "protocols" / "lamp.json"
    with tempfile.TemporaryDirectory() as tmp:
        target = Path(tmp) / "p.json"
        loads(src.read_text()).save(target)
        for i in range(n):
            w = subprocess.Popen([sys.executable, "-c", WRITER, str(src), str(target)])
            time.sleep(rng.uniform(0.3, 1.5))
            w.kill()
            w.wait()
            try:
                loads(target.read_text())
                tally.add("accepted")
            except ProtocolError:
                tally.add("broken", case=f"kill {i}")
            loads(src.read_text()).save(target)  # the next write
            left = [p for p in Path(tmp).iterdir() if MARK in p.name]
            if left:
                tally.add("leftover", case=f"kill {i}: {left}")
    return tally


def concurrent_writers(seconds: float) -> Tally:
    """Two writers of one file for `seconds` while this process reads it."""
    tally = Tally()
    src = ROOT / "examples" / "protocols" / "lamp.json"
    with tempfile.TemporaryDirectory() as tmp:
        target = Path(tmp) / "p.json"
        loads(src.read_text()).save(target)
        writers = [
            subprocess.Popen(
                [sys.executable, "-c", WRITER, str(src), str(target)], stderr=subprocess.PIPE
            )
            for _ in range(2)
        ]
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            try:
                loads(target.read_text())
                tally.add("accepted")
            except ProtocolError:
                tally.add("broken")
            except OSError:
                tally.add("crash")
        for w in writers:
            w.kill()
            w.wait()
            if w.poll() not in (-9, 0):
                tally.add("crash", case=w.stderr.read().decode()[-300:])
    return tally


def output_targets(seed: int) -> Tally:
    """A protocol saved onto every kind of path a user may name: a new file, a file, a
    link to one, a dangling link, a link into /proc (as /dev/stdout), a device node made
    here (as /dev/null), a full device (as /dev/full), a FIFO with a reader, a folder, a
    path under a file. A write must land where the path leads and leave each kind what
    it was ("accepted"), or fail with an OSError naming the path ("clean"); a device,
    link or FIFO turned into a regular file is "changed", a temporary left "leftover"."""
    import errno
    import os
    import stat
    import threading

    rng, tally = random.Random(seed), Tally()
    protocol = loads((ROOT / "examples" / "protocols" / "nut.json").read_text())
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "file.json").write_text("old")
        (tmp / "link.json").symlink_to("file.json")
        (tmp / "dangling.json").symlink_to("later.json")
        (tmp / "folder").mkdir()
        kinds = {"new": tmp / "new.json", "file": tmp / "file.json"}
        kinds.update(link=tmp / "link.json", dangling=tmp / "dangling.json")
        kinds.update(folder=tmp / "folder", under_file=tmp / "file.json" / "x.json")
        try:
            os.mknod(tmp / "null", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
            os.mknod(tmp / "full", 0o666 | stat.S_IFCHR, os.makedev(1, 7))
            kinds.update(device=tmp / "null", full=tmp / "full")
        except PermissionError:  # device nodes need root: the other kinds still run
            pass
        os.mkfifo(tmp / "fifo")
        kinds["fifo"] = tmp / "fifo"
        names = sorted(kinds)
        rng.shuffle(names)
        for name in names:
            path = kinds[name]
            before = os.lstat(path).st_mode if os.path.lexists(path) else None
            reader = None
            if name == "fifo":
                reader = threading.Thread(target=path.read_bytes, daemon=True)
                reader.start()
            t = time.perf_counter()
            try:
                protocol.save(path)
                outcome = "accepted"
            except OSError as e:
                named = str(path) in str(e) and MARK not in str(e)
                full = name != "full" or e.errno == errno.ENOSPC
                outcome = "clean" if named and full else "crash"
                case = f"{name}: {e}"
            else:
                case = name
            if reader:
                reader.join(10)
            after = os.lstat(path).st_mode if os.path.lexists(path) else None
            if before is not None and stat.S_IFMT(before) != stat.S_IFMT(after or 0):
                outcome = "changed"
            if name in ("link", "dangling") and outcome == "accepted":
                target = path.resolve()
                if loads(target.read_text()) != protocol:
                    outcome = "broken"
            tally.add(outcome, time.perf_counter() - t, case)
        left = [p for p in tmp.rglob("*") if MARK in p.name]
        if left:
            tally.add("leftover", case=str(left))
    return tally


def hostile_geometry(n: int, seed: int) -> Tally:
    """n protocols of a box and one operation that is not what it says: a bevel whose
    corner c lies inside f (a random point of a side face), a sweep whose profile c_p
    folds back in h (random inner heights outside [0, d]). Each must be refused
    ("clean"); one that builds is "invalid"."""
    from Sketch2CADWorkbench.brep.protocol import Bevel, Box, FaceRef, Protocol, Sweep

    rng, tally = random.Random(seed), Tally()
    for i in range(n):
        lx, ly, lz = (rng.uniform(20, 80) for _ in range(3))
        box = Box((lx, ly, lz))
        if i % 2 == 0:
            x, z = rng.uniform(-0.3, 0.3) * lx, rng.uniform(-0.3, 0.3) * lz
            a, b = rng.uniform(2, 0.15 * lz), rng.uniform(2, 0.15 * lx)
            y = -ly / 2
            face = FaceRef((x, y, z), (0.0, -1.0, 0.0))
            profile = ((x, y, z - a), (x, y, z - a / 2), (x + b / 2, y, z), (x + b, y, z))
            op = Bevel(face, (x, y, z), (x, ly / 2, z), profile)
        else:
            d, r = rng.uniform(3, 20), rng.uniform(2, 8)
            h1 = rng.uniform(1.2, 3.0) * d
            h2 = -rng.uniform(0.2, 2.0) * d
            face = FaceRef((0.0, 0.0, lz / 2), (0.0, 0.0, 1.0))
            op = Sweep(face, (0.0, 0.0, lz / 2), r, r, d, ((r, h1), (r, h2)))
        tally.add(*_classify(lambda box=box, op=op: build(Protocol(box, (op,))), f"geometry {i}"))
    tally.counts["invalid"] += tally.counts.pop("accepted", 0)
    return tally
