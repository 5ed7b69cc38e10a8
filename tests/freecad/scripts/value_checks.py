# SPDX-License-Identifier: LGPL-2.1-or-later
"""Impossible property values typed into the features (#12), run by test_values.py in one
freecadcmd process: each puts its own step in error with a message that names the
property (or the parameter and its range) and no OCCT text, the later steps follow it
into error, and typing the old value back rebuilds the model as it was."""
import os
import sys

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD  # noqa: E402
from harness import EXAMPLES, check, close, finish, run_checks, say, tested_checkout  # noqa: E402

from Sketch2CADWorkbench.brep.protocol import load  # noqa: E402
from Sketch2CADWorkbench.freecad_layer.make.make_model import make_model_from_protocol  # noqa: E402
from Sketch2CADWorkbench.freecad_layer.queries import failed_features, features  # noqa: E402

NAN, INF = float("nan"), float("inf")
V = FreeCAD.Vector
# what OCCT says when it is handed such values: none of it may reach the user
OCCT_TEXTS = ("BRep", "wires not planar", "gp_", "Standard_", "TopoDS", "OCCT", "Null")


def _feature(model, kind: str):
    return next(o for o in features(model) if o.Proxy.TYPE == f"Sketch2CAD::{kind}")


def _lists(chain) -> dict:
    """The point lists of the steps (a sweep retunes its profile when a radius changes)."""
    return {(o.Name, p): getattr(o, p) for o in chain for p in ("ProfileInner", "Polygon")
            if hasattr(o, p)}


def _same(a: dict, b: dict) -> bool:
    """The same point lists, to a relative 1e-9 (a retune there and back rounds)."""
    return a.keys() == b.keys() and all(
        len(a[k]) == len(b[k]) and all(close(p[i], q[i], 1e-9) or abs(p[i] - q[i]) < 1e-9
                                       for p, q in zip(a[k], b[k]) for i in range(3))
        for k in a)


def _polygon(prism, change):
    return [change(i, V(p)) for i, p in enumerate(prism.Polygon)]


# (feature kind, property, value or function of the feature giving it, expected text)
CASES = [
    ("Box", "Length", 0.0, "Length = 0 mm; a side of the box must be from"),
    ("Box", "Width", 1e-12, "Width = 1e-12 mm; a side of the box must be from"),
    ("Box", "Height", 1e300, "Height = 1e+300 mm; a side of the box must be from"),
    ("Box", "Length", NAN, "Length is nan; type a finite number"),
    ("Box", "Length", INF, "Length = 1.79769e+308 mm; a side of the box"),  # FreeCAD clamps inf
    ("Extrude", "Offset", NAN, "Offset is nan; type a finite number"),
    ("Extrude", "Offset", INF, "Offset is inf; type a finite number"),
    ("Extrude", "Offset", 0.0, "d = 0 mm is out of range for this model"),
    ("Extrude", "Offset", -1e300, "d = -1e+300 mm is out of range for this model"),
    ("Extrude", "FaceNormal", V(NAN, 0, 1), "FaceNormal.x is nan; type a finite number"),
    ("Extrude", "FacePoint", V(0, INF, 0), "FacePoint.y is inf; type a finite number"),
    ("AddSubPrism", "Length", NAN, "Length is nan; type a finite number"),
    ("AddSubPrism", "Length", 1e-12, "d = 1e-12 mm is out of range for this model"),
    ("AddSubPrism", "Polygon", lambda o: _polygon(o, lambda i, p: V(NAN, p.y, p.z) if i == 1 else p),
     "Polygon[1].x is nan; type a finite number"),
    ("AddSubPrism", "Polygon", lambda o: _polygon(o, lambda i, p: V(o.Polygon[0])),
     "polygon vertices 0 and 1 coincide"),
    ("AddSubPrism", "Polygon", lambda o: _polygon(o, lambda i, p: p * 1e300),
     "polygon lies"),
    ("AddSubPrism", "Polygon", lambda o: [V(o.Polygon[0]), (o.Polygon[0] + o.Polygon[1]) * 0.5,
                                          V(o.Polygon[1])], "base polygon c has no area"),
    ("AddSubPrism", "Polygon", lambda o: [V(o.Polygon[i]) for i in (0, 2, 1, 3)],
     "cross each other"),  # a bow tie
    ("Sweep", "Radius0", NAN, "Radius0 is nan; type a finite number"),
    ("Sweep", "Radius1", INF, "r1 = 1.79769e+308 mm is out of range"),  # FreeCAD clamps inf
    ("Sweep", "Offset", NAN, "Offset is nan; type a finite number"),
    ("Sweep", "Radius0", 0.0, "r0 = 0 mm is out of range"),
    ("Sweep", "Center", V(NAN, 0, 0), "Center.x is nan; type a finite number"),
]


@check
def impossible_values_are_refused_naming_the_property_and_lose_nothing():
    tested_checkout()
    doc = FreeCAD.newDocument("values")
    model = make_model_from_protocol(doc, load(os.path.join(EXAMPLES, "lamp.json")))
    chain = features(model)
    volumes = [o.Shape.Volume for o in chain]
    failures = []
    for kind, prop, value, expected in CASES:
        obj = _feature(model, kind)
        old = getattr(obj, prop)
        kept = _lists(chain)
        setattr(obj, prop, value(obj) if callable(value) else value)
        doc.recompute()
        failed = failed_features(model)
        status = failed[0].getStatusString() if failed else "built"
        case = f"{kind}.{prop} = {str(value)[:30]}"
        if not failed or failed[0] != obj or failed != chain[chain.index(obj):]:
            failures.append(f"{case}: the failed steps are {[o.Label for o in failed]}")
        elif expected not in status or any(t in status for t in OCCT_TEXTS):
            failures.append(f"{case}: {status!r} does not say {expected!r}")
        setattr(obj, prop, old)
        doc.recompute()
        if failed_features(model) or not all(
                close(o.Shape.Volume, v) for o, v in zip(chain, volumes)) or not _same(_lists(chain), kept):
            failures.append(f"{case}: typing the old value back did not restore the model")
            FreeCAD.closeDocument(doc.Name)
            doc = FreeCAD.newDocument("values")
            model = make_model_from_protocol(doc, load(os.path.join(EXAMPLES, "lamp.json")))
            chain = features(model)
    say(f"FIGURE impossible_values_refused {len(CASES) - len(failures)}/{len(CASES)}")
    assert not failures, "\n".join(failures)


@check
def a_huge_face_normal_is_a_direction_not_a_zero_vector():
    """(1e300, 1e300, 0) has a length that overflows; it still names a direction."""
    doc = FreeCAD.newDocument("normal")
    model = make_model_from_protocol(doc, load(os.path.join(EXAMPLES, "lamp.json")))
    extrude = _feature(model, "Extrude")
    n = V(extrude.FaceNormal)
    extrude.FaceNormal = n * 1e300
    doc.recompute()
    try:
        assert extrude.Proxy.face(extrude).normal == (n.x, n.y, n.z), extrude.Proxy.face(extrude)
        assert not failed_features(model), [o.getStatusString() for o in failed_features(model)]
    finally:
        FreeCAD.closeDocument(doc.Name)


finish(run_checks())
