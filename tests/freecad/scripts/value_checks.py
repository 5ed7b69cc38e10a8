# SPDX-License-Identifier: LGPL-2.1-or-later
"""Impossible property values typed into the features, run by test_values.py in one
freecadcmd process: each puts its own step in error with a message that names the
property (or the parameter and its range) and no OCCT text, the later steps follow it
into error, and typing the old value back rebuilds the model as it was."""

import os
import sys

sys.path.insert(0, os.path.join(os.environ["SKETCH2CAD_ROOT"], "tests", "freecad", "scripts"))
import FreeCAD
from harness import EXAMPLES, check, close, finish, run_checks, say, tested_checkout

from Sketch2CADWorkbench.brep.protocol import load
from Sketch2CADWorkbench.freecad_layer.make.make_model import make_model_from_protocol
from Sketch2CADWorkbench.freecad_layer.queries import failed_features, features

NAN, INF = float("nan"), float("inf")
V = FreeCAD.Vector
# what OCCT says when it is handed such values: none of it may reach the user
OCCT_TEXTS = ("BRep", "wires not planar", "gp_", "Standard_", "TopoDS", "OCCT", "Null")


def _feature(model, kind: str):
    return next(o for o in features(model) if f"Sketch2CAD::{kind}" == o.Proxy.TYPE)


def _lists(chain) -> dict:
    """The polygons' vertices and the sweeps' inner profile points (a sweep retunes its
    profile when a radius changes), as numbers."""
    return {
        (o.Name, p): _floats(getattr(o, p))
        for o in chain
        for p in o.PropertiesList
        if p.startswith(("Vertex", "Control"))
    }


def _floats(v) -> tuple:
    return (v.x, v.y, v.z) if isinstance(v, FreeCAD.Vector) else (float(getattr(v, "Value", v)),)


def _same(a: dict, b: dict) -> bool:
    """The same points, to a relative 1e-9 (a retune there and back rounds)."""
    return a.keys() == b.keys() and all(
        close(p, q, 1e-9) or abs(p - q) < 1e-9 for k in a for p, q in zip(a[k], b[k], strict=False)
    )


def _vertices(prism) -> list:
    return [V(getattr(prism, p)) for p in prism.PropertiesList if p.startswith("Vertex")]


def _polygon(change):
    """Changes of a prism's vertices (Vertex1...): change(i, point, all points) -> point."""

    def changes(prism):
        pts = _vertices(prism)
        return {f"Vertex{i + 1}": change(i, p, pts) for i, p in enumerate(pts)}

    return changes


# (feature kind, {property: value} or a function of the feature giving it, expected text)
CASES = [
    ("Box", {"Length": 0.0}, "Length = 0 mm; a side of the box must be from"),
    ("Box", {"Width": 1e-12}, "Width = 1e-12 mm; a side of the box must be from"),
    ("Box", {"Height": 1e300}, "Height = 1e+300 mm; a side of the box must be from"),
    ("Box", {"Length": NAN}, "Length is nan; type a finite number"),
    ("Box", {"Length": INF}, "Length = 1.79769e+308 mm; a side of the box"),  # FreeCAD clamps inf
    ("Extrude", {"Offset": NAN}, "Offset is nan; type a finite number"),
    ("Extrude", {"Offset": INF}, "Offset is inf; type a finite number"),
    ("Extrude", {"Offset": 0.0}, "d = 0 mm is out of range for this model"),
    ("Extrude", {"Offset": -1e300}, "d = -1e+300 mm is out of range for this model"),
    ("Extrude", {"FaceNormal": V(NAN, 0, 1)}, "FaceNormal.x is nan; type a finite number"),
    ("Extrude", {"FacePoint": V(0, INF, 0)}, "FacePoint.y is inf; type a finite number"),
    ("AddSubPrism", {"Length": NAN}, "Length is nan; type a finite number"),
    ("AddSubPrism", {"Length": 1e-12}, "d = 1e-12 mm is out of range for this model"),
    ("AddSubPrism", {"Vertex2": V(NAN, 0, 0)}, "Vertex2.x is nan; type a finite number"),
    ("AddSubPrism", lambda o: {"Vertex2": V(o.Vertex1)}, "polygon vertices 0 and 1 coincide"),
    ("AddSubPrism", _polygon(lambda i, p, pts: p * 1e300), "polygon lies"),
    (
        "AddSubPrism",
        _polygon(lambda i, p, pts: pts[0] + (pts[1] - pts[0]) * i),
        "base polygon c has no area",
    ),  # every vertex on one line
    (
        "AddSubPrism",
        _polygon(lambda i, p, pts: pts[{1: 2, 2: 1}.get(i, i)]),
        "cross each other",
    ),  # a bow tie
    ("Sweep", {"Radius0": NAN}, "Radius0 is nan; type a finite number"),
    ("Sweep", {"Radius1": INF}, "r1 = 1.79769e+308 mm is out of range"),  # FreeCAD clamps inf
    ("Sweep", {"Offset": NAN}, "Offset is nan; type a finite number"),
    ("Sweep", {"Radius0": 0.0}, "r0 = 0 mm is out of range"),
    ("Sweep", {"Center": V(NAN, 0, 0)}, "Center.x is nan; type a finite number"),
]


@check
def impossible_values_are_refused_naming_the_property_and_lose_nothing():
    tested_checkout()
    doc = FreeCAD.newDocument("values")
    model = make_model_from_protocol(doc, load(os.path.join(EXAMPLES, "lamp.json")))
    chain = features(model)
    volumes = [o.Shape.Volume for o in chain]
    failures = []
    for kind, changes, expected in CASES:
        obj = _feature(model, kind)
        changes = changes(obj) if callable(changes) else changes
        old = {prop: getattr(obj, prop) for prop in changes}
        kept = _lists(chain)
        for prop, value in changes.items():
            setattr(obj, prop, value)
        doc.recompute()
        failed = failed_features(model)
        status = failed[0].getStatusString() if failed else "built"
        case = f"{kind} {str(changes)[:60]}"
        if not failed or failed[0] != obj or failed != chain[chain.index(obj) :]:
            failures.append(f"{case}: the failed steps are {[o.Label for o in failed]}")
        elif expected not in status or any(t in status for t in OCCT_TEXTS):
            failures.append(f"{case}: {status!r} does not say {expected!r}")
        for prop, value in old.items():
            setattr(obj, prop, value)
        doc.recompute()
        if (
            failed_features(model)
            or not all(close(o.Shape.Volume, v) for o, v in zip(chain, volumes, strict=False))
            or not _same(_lists(chain), kept)
        ):
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
