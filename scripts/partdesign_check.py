# SPDX-License-Identifier: LGPL-2.1-or-later
"""How much of each model converts into native PartDesign features, exactly.

    freecadcmd scripts/partdesign_check.py

Converts every example protocol and random valid protocols (the data generator's
sequences of 1 to 4 operations on planar faces, and a quarter with a last step on a
cylinder's or cone's side, as datagen/curved.py draws them), a tenth as many more
ending in a shell, then random protocols ending in a round, chamfer or profile across an
edge (datagen/rounds.py; each from a generator of its own, so that the others stay the
same) into PartDesign Bodies
(freecad_layer/partdesign) and prints the share of steps converted exactly (a native
feature whose solid matches the core's: volume within 1e-6 relative, symmetric
difference below 1e-6 of the volume), per operator and in all, and the reasons of the
others; fillets and chamfers are counted on their own. Settings through the
environment (freecadcmd passes no arguments to a script): SKETCH2CAD_PD_COUNT (random
protocols, default 300), SKETCH2CAD_PD_ROUNDS (those ending in a round, default 50),
SKETCH2CAD_PD_SEED (default 1).
This checkout is imported, whatever FreeCAD's Mod folder holds. Exits 1 when a
conversion raised an error.
"""

import os
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
for _name in [m for m in sys.modules if m.split(".")[0] == "Sketch2CADWorkbench"]:
    del sys.modules[_name]  # a workbench loaded from FreeCAD's Mod folder: use this checkout
from Sketch2CADWorkbench.freecad_layer import env  # noqa: E402

env.bootstrap()

import FreeCAD  # noqa: E402
import numpy as np  # noqa: E402

from datagen.curved import curved_context, draw_kind, sample_on_curved  # noqa: E402
from datagen.sequences import TRIES, sample_operation, sample_sequence  # noqa: E402
from Sketch2CADWorkbench.brep.faces import OperationError  # noqa: E402
from Sketch2CADWorkbench.brep.operators import operation_result  # noqa: E402
from Sketch2CADWorkbench.brep.protocol import OperatorType, Protocol, load  # noqa: E402
from Sketch2CADWorkbench.freecad_layer.partdesign.convert import convert_protocol  # noqa: E402

CURVED_SHARE = 0.25
SHELL_SHARE = 0.1  # protocols ending in a shell, beside the random ones
ROUNDS = ("Fillet", "Chamfer")


def random_protocol(rng: np.random.Generator) -> Protocol:
    """A valid protocol: 1 to 4 random operations, or (CURVED_SHARE) a context ending in
    a straight sweep with a last operation on its curved side."""
    if rng.random() >= CURVED_SHARE:
        return sample_sequence(rng, int(rng.integers(1, 5))).protocol
    while True:
        seq, faces = curved_context(rng)
        kind = draw_kind(rng)
        for _ in range(TRIES):
            got = sample_on_curved(rng, faces[int(rng.integers(len(faces)))], kind)
            if got is None:
                continue
            try:
                operation_result(seq.stages[-1].solid, got[0])
            except OperationError:
                continue
            return seq.protocol.append(got[0])


def round_protocol(rng: np.random.Generator) -> Protocol:
    """A valid protocol of 1 to 4 operations whose last is a bevel across an edge."""
    while True:
        seq = sample_sequence(rng, int(rng.integers(0, 4)))
        got = sample_operation(rng, seq.stages[-1], OperatorType.BEVEL, round_share=1.0)
        if got is not None:
            return seq.protocol.append(got.op)


def main() -> int:
    count = int(os.environ.get("SKETCH2CAD_PD_COUNT", "300"))
    seed = int(os.environ.get("SKETCH2CAD_PD_SEED", "1"))
    print(
        f"FreeCAD {'.'.join(FreeCAD.Version()[:3])}: examples, {count} random protocols and "
        f"{int(SHELL_SHARE * count)} ending in a shell"
    )
    cases = [(p.stem, load(p)) for p in sorted((ROOT / "examples" / "protocols").glob("*.json"))]
    rng = np.random.default_rng(seed)
    cases += [(f"random-{seed}-{i}", random_protocol(rng)) for i in range(count)]
    shells = np.random.default_rng([seed, 1])
    cases += [
        (
            f"random-shell-{seed}-{i}",
            sample_sequence(shells, int(shells.integers(1, 5)), OperatorType.SHELL).protocol,
        )
        for i in range(int(SHELL_SHARE * count))
    ]
    rounds = int(os.environ.get("SKETCH2CAD_PD_ROUNDS", "50"))
    round_rng = np.random.default_rng([seed, 2])  # the other protocols stay as they were
    cases += [(f"random-{seed}-round-{i}", round_protocol(round_rng)) for i in range(rounds)]
    tally = {"examples": Counter(), "random": Counter()}
    reasons, errors, cases_left, start = Counter(), [], [], time.monotonic()
    for name, protocol in cases:
        group = "random" if name.startswith("random") else "examples"
        doc = FreeCAD.newDocument("check")
        try:
            conversion = convert_protocol(doc, protocol)
        except Exception:  # a crash of the conversion is what this check looks for
            errors.append(f"{name}: {traceback.format_exc()}")
            continue
        finally:
            FreeCAD.closeDocument(doc.Name)
        for step in conversion.steps:
            # fillets and chamfers (bevels whose profile is regular) counted on their own
            operator = step.label.lower() if step.label in ROUNDS else step.operator
            tally[group][(operator, "all")] += 1
            tally[group][(operator, "native")] += step.native
            if not step.native:
                reasons[f"{operator}: {step.reason.split(' (')[0]}"] += 1
                cases_left.append(f"{name} step {step.step} ({step.label}): {step.reason}")
    for group, counts in tally.items():
        print(f"{group}: steps converted exactly, per operator")
        operators = sorted({op for op, _ in counts})
        for op in operators + ["in all"]:
            keys = operators if op == "in all" else [op]
            n = sum(counts[(k, "all")] for k in keys)
            ok = sum(counts[(k, "native")] for k in keys)
            print(f"  {op:8s} {ok:4d} / {n:4d}  {100.0 * ok / max(n, 1):6.2f}%")
    for reason, n in reasons.most_common():
        print(f"not native ({n}): {reason}")
    for case in cases_left:
        print(f"  {case}")
    for error in errors:
        print(f"ERROR {error}")
    print(f"{len(cases)} protocols in {time.monotonic() - start:.0f} s, {len(errors)} errors")
    return 1 if errors else 0


code = main()
sys.stdout.flush()
os._exit(code)  # freecadcmd exits 0 on an uncaught exception; this does not
