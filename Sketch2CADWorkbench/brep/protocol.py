# SPDX-License-Identifier: LGPL-2.1-or-later
"""The protocol: typed operations with the paper's parameters, and its versioned JSON.

A protocol is a base box followed by operations applied in order (paper, "Protocols
for CAD modeling"). All lengths are in millimetres, all points and vectors in the
model's world frame. A base face is stored geometrically (`FaceRef`: a point inside
the face, its outward normal there, and the kind of its surface), never as a face
index, so that replay resolves it against whatever solid the earlier steps produced.

Base faces may be curved (beyond the paper, whose first limitation this is): the side
of a cylinder or a cone, as sweeps make them. On a curved f the operators work in the
tangent plane T of f at the FaceRef point p_f, whose normal is n_f there: a prism's
polygon c and a sweep's circle c0 lie in T and the primitive stands along n_f from it
(into the body as far as the curved surface needs, so that it meets f without a gap,
brep/operators), and an extrusion moves the whole face along its normal, so a
cylinder's radius grows (d > 0) or shrinks (d < 0) by |d|.

When an earlier step is edited, the later ones follow what they were made on: f is the
face that holds the point, or the nearest one with the same normal whose outline holds
its projection; a prism's polygon and a sweep's circle move with f's plane; a bevel's
corner is found again where it moved to (`Bevel`). A step that no longer fits is an
error naming the field and why. The file keeps the values as the step was made, so
edits need no new schema.

JSON schema, version 3 (every key required unless marked optional)::

    {"format": "sketch2cad-protocol", "version": 3, "units": "mm",
     "base": {"type": "box", "size": [lx, ly, lz]},          # centred on the origin
     "operations": [
       {"type": "extrude", "face": FACE, "d": float},
       {"type": "bevel", "face": FACE, "corner": P, "opposite": P,
        "profile": [P, P, P, P],         # cubic Bezier on f; c found again on replay
        "edges": EDGES,                  # optional, "drawn" by default
        "radius": float | "distances": [d1, d2]},   # optional: a fillet or a chamfer
       {"type": "addsub", "face": FACE, "polygon": [P, P, P, ...],   # 3 to 6 points
        "d": float, "mode": MODE},
       {"type": "sweep", "face": FACE, "center": P, "r0": float, "r1": float,
        "d": float, "profile": [[r, h], [r, h]], "mode": MODE},
       {"type": "shell", "face": FACE, "t": float}]}      # f opened, walls t > 0 thick
    FACE = {"point": P, "normal": P, "surface": SURFACE}   # "surface" optional
    SURFACE = "plane" (the default) | "cylinder" | "cone"; P = [x, y, z]
    MODE = "add" | "subtract" | "intersect" | "replace"
    EDGES = "drawn" | "chain" | "outline"

A bevel without "opposite" is drawn across an edge of f at c (`Bevel`). The bevel's
optional keys are written only when they differ from their defaults, so a file without
them loads unchanged and is written back as it was.

Version 2 is version 3 without "shell"; version 1 is version 2 without "surface"
(every face planar). Older files load unchanged, and a protocol is written with the
lowest version that holds it (`protocol_version`), so that builds which read only an
older version keep reading what they can build.

`validate` style: every loader error names the field path and the offending value.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import numpy as np

from .fields import FieldError, box_size, error, header, number, obj, parse_json, points, vec
from .files import read_capped, write_atomically
from .geometry import bezier

FORMAT = "sketch2cad-protocol"
VERSION = 3  # the newest; VERSIONS are the ones this build reads
VERSIONS = (1, 2, 3)

Vec3 = tuple[float, float, float]
Vec2 = tuple[float, float]


class OperatorType(Enum):
    """The four operators of the paper, then the shell (beyond the paper).

    The U-Net classifies the paper's four (`sketch.labels.CLASSES`), the structured head
    all five (`sketch.labels.LABELLED`).
    """

    EXTRUDE = "extrude"
    BEVEL = "bevel"
    ADDSUB = "addsub"
    SWEEP = "sweep"
    SHELL = "shell"


class Mode(Enum):
    """The Boolean between the current solid and a sketched primitive (option o).

    ADD (o=+) and SUBTRACT (o=-) are the paper's options; INTERSECT and REPLACE
    (keep only the primitive) let a model start from a shape other than the box.
    """

    ADD = "add"
    SUBTRACT = "subtract"
    INTERSECT = "intersect"
    REPLACE = "replace"

    @property
    def sign(self) -> float:
        """Direction of the primitive along the face normal: inwards only for SUBTRACT."""
        return -1.0 if self is Mode.SUBTRACT else 1.0

    @property
    def flipped(self) -> Mode | None:
        """The other option of an addition or subtraction; None for intersect and
        replace, which have none."""
        return {Mode.ADD: Mode.SUBTRACT, Mode.SUBTRACT: Mode.ADD}.get(self)


class ProtocolError(FieldError):
    """A protocol file or value is malformed; the message names the field and value."""


class OperationError(ValueError):
    """An operation cannot be built on the given solid; the message says why."""


class WallTooThick(OperationError):
    """A shell's t is more than the solid takes: walls t thick from every face leave no
    cavity, or offset walls cross. A smaller t may build."""


T = TypeVar("T")


def per_operator(table: dict[OperatorType, T], what: str) -> dict[OperatorType, T]:
    """A table of per-operator behaviour, keyed by `OperatorType`, checked to have one
    entry for each operator when its module is imported.

    Behaviour of the protocol itself (JSON, description, mirror image) lives on the
    operation dataclasses; every other layer keeps what it does per operator (B-rep
    builders, sketch curves, samplers, fits, FreeCAD features) in such a table, looked
    up with `TABLE[op.type]`.

    Raises:
        TypeError: an operator is missing or a key is not an `OperatorType`.
    """
    missing = [t.value for t in OperatorType if t not in table]
    extra = [k for k in table if not isinstance(k, OperatorType)]
    if missing or extra:
        raise TypeError(
            f"{what}: one entry per OperatorType expected; missing {missing}, not operators {extra}"
        )
    return table


def _num(x: float) -> str:
    # to the micrometre (mm units), and no "-0" or "1e-15" from round-off
    return f"{round(x, 3) + 0.0:g}"


def _fmt(v) -> str:
    return "(" + ", ".join(_num(x) for x in v) + ")"


def _fail(path: str, msg: str, value: Any) -> ProtocolError:
    return ProtocolError(str(error(path, msg, value)))


def _unit(v: Any, path: str) -> Vec3:
    x = vec(v, path)
    n = math.sqrt(sum(c * c for c in x))
    if n < 1e-9:
        raise _fail(path, "expected a non-zero normal vector", v)
    if abs(n - 1.0) > 1e-6:
        raise _fail(path, "expected a unit normal vector (length 1)", v)
    return x  # type: ignore[return-value]


def _mode(v: Any, path: str) -> Mode:
    try:
        return Mode(v)
    except ValueError:
        raise _fail(path, f"expected one of {[m.value for m in Mode]}", v) from None


# A mirror: world point -> mirrored point, world vector -> mirrored vector.
PointMap = Callable[[Vec3], Vec3]


class Surface(Enum):
    """The kind of surface a base face f lies on."""

    PLANE = "plane"
    CYLINDER = "cylinder"
    CONE = "cone"

    @property
    def curved(self) -> bool:
        return self is not Surface.PLANE


@dataclass(frozen=True)
class FaceRef:
    """A base face f: a point p_f on it, its outward unit normal n_f there (world, mm),
    and the kind of surface it lies on.

    On a planar f, p_f is any point inside it. On a curved f (a cylinder's or cone's
    side), p_f is where the step stands: its tangent plane there is the plane the
    step's polygon or circle is given in (module docstring).
    """

    point: Vec3
    normal: Vec3
    surface: Surface = Surface.PLANE

    def describe(self) -> str:
        kind = f"{self.surface.value} " if self.surface.curved else ""
        return f"f[{kind}n={_fmt(self.normal)} at {_fmt(self.point)}]"

    def to_dict(self) -> dict[str, Any]:
        out = {"point": list(self.point), "normal": list(self.normal)}
        if self.surface.curved:
            out["surface"] = self.surface.value
        return out

    @staticmethod
    def from_dict(v: Any, path: str) -> FaceRef:
        o = obj(v, path, {"point", "normal"}, {"surface"})
        surface = Surface.PLANE
        if "surface" in o:
            try:
                surface = Surface(o["surface"])
            except ValueError:
                raise _fail(
                    f"{path}.surface", f"expected one of {[s.value for s in Surface]}", o["surface"]
                ) from None
        return FaceRef(
            vec(o["point"], f"{path}.point"), _unit(o["normal"], f"{path}.normal"), surface
        )

    def reflected(self, point: PointMap, vector: PointMap) -> FaceRef:
        return FaceRef(point(self.point), vector(self.normal), self.surface)


@dataclass(frozen=True)
class Box:
    """The base shape: an axis-aligned box of size (lx, ly, lz) mm centred on the origin."""

    size: Vec3


class _Operation:
    """What every operation of the protocol does; each dataclass below fills it in.

    Class attributes: `type` (its OperatorType), `KEYS` (its JSON keys besides "type"
    and "face", in the order they are written) and `OPTIONAL` (those of KEYS it may
    leave out: written only when they differ from their default, so that older files
    load unchanged and are written again as they were).
    """

    type: ClassVar[OperatorType]
    KEYS: ClassVar[tuple[str, ...]]
    OPTIONAL: ClassVar[tuple[str, ...]] = ()
    NOUN: ClassVar[str]  # what errors call it: "extrude", "bevel", "prism", "sweep"
    face: FaceRef

    @property
    def boolean(self) -> Mode:
        """How the operation's primitive combines with the solid."""
        return Mode.SUBTRACT

    @property
    def name(self) -> str:
        """The step as errors name it ("extrude", "add prism", ...)."""
        return self.NOUN

    def check(self) -> None:
        """Refuse parameter values no solid can take (the solid's own checks come later).

        Raises:
            OperationError: naming the parameter and its value.
        """

    def describe(self) -> str:
        """One line naming the operator and its parameters with the paper's symbols."""
        raise NotImplementedError

    def version_needed(self) -> tuple[int, str, str]:
        """The lowest schema version that holds the operation, with the field (relative to
        the operation) that needs it and why, for the loader's error."""
        if self.face.surface.curved:
            return (
                2,
                "face.surface",
                "a curved base face needs version 2 (version 1 has planar faces only)",
            )
        return 1, "", ""

    def parameters(self) -> dict[str, Any]:
        """The JSON values of KEYS."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        """The operation as a JSON object (schema in the module docstring)."""
        return {"type": self.type.value, "face": self.face.to_dict(), **self.parameters()}

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> _Operation:
        """The operation from a JSON object `o` that holds exactly its keys (checked);
        raises FieldError naming the field and value."""
        raise NotImplementedError

    def reflected(self, point: PointMap, vector: PointMap) -> _Operation:
        """The operation mirrored: `point` and `vector` map world points and vectors."""
        raise NotImplementedError


@dataclass(frozen=True)
class Extrude(_Operation):
    """Move face f along its outward normal by d mm (d > 0 pads, d < 0 pockets)."""

    face: FaceRef
    d: float

    type = OperatorType.EXTRUDE
    KEYS = ("d",)
    NOUN = "extrude"

    @property
    def boolean(self) -> Mode:
        """A pad fuses, a pocket cuts."""
        return Mode.ADD if self.d > 0 else Mode.SUBTRACT

    def check(self) -> None:
        if self.d == 0 or not math.isfinite(self.d):
            raise OperationError(f"extrude: offset d must be a non-zero number, got {self.d}")

    def describe(self) -> str:
        return f"Extrude {self.face.describe()} d={_num(self.d)}"

    def parameters(self) -> dict[str, Any]:
        return {"d": self.d}

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> Extrude:
        return cls(face, number(o["d"], f"{path}.d", nonzero=True))

    def reflected(self, point: PointMap, vector: PointMap) -> Extrude:
        return Extrude(self.face.reflected(point, vector), self.d)


class EdgeSet(Enum):
    """Which edges a bevel follows (its `edges` field)."""

    DRAWN = "drawn"  # the edge the profile is drawn across
    CHAIN = "chain"  # the tangent-continuous chain of edges through it
    OUTLINE = "outline"  # every edge of face f's outline ("round the top")


@dataclass(frozen=True)
class Bevel(_Operation):
    """Round or chamfer an edge with profile l, drawn across it from one face to the other.

    Two forms. The paper's (a crease): `corner` is c, a corner of f where two straight
    edges of f meet and an edge of the solid, the crease, leaves it into the solid along
    -n_f; `opposite` is c' (the crease's other end, so c' - c points along -n_f);
    `profile` is l, the four control points of a cubic Bezier on f's plane from one edge
    of f at c to the other. Across an edge (`opposite` None): f is a planar face on one
    side of the edge, `corner` is c, the point of the edge that l crosses, and l lies in
    the plane through c normal to the edge, from f (l(0)) to the face on the other side
    (l(1)); the edge may be straight or a circular rim (a plane meeting a cylinder or a
    cone, as sweeps make), around which l is revolved.

    `edges` says which edges the step follows (`EdgeSet`; the crease form follows its
    crease or that crease's tangent chain). `radius` makes it a true constant-radius
    fillet, `distances` (d1 on f's side, or l(0)'s, then d2) a chamfer, both built by
    OCCT on every edge of the set; without them l itself is cut, along one straight edge
    or around one rim (brep/operators.bevel_edges says what else OCCT allows).

    They record the bevel as it was made. On replay the corner is found again on the
    solid as it is then: when an earlier step was edited and c moved (f grew or
    shrank), the bevel moves with it, and the crease runs along the solid's edge from c
    to wherever its far end is now (brep/operators.place_bevel).
    """

    face: FaceRef
    corner: Vec3
    opposite: Vec3 | None
    profile: tuple[Vec3, Vec3, Vec3, Vec3]
    edges: EdgeSet = EdgeSet.DRAWN
    radius: float | None = None
    distances: tuple[float, float] | None = None

    type = OperatorType.BEVEL
    KEYS = ("corner", "opposite", "profile", "edges", "radius", "distances")
    OPTIONAL = ("opposite", "edges", "radius", "distances")
    NOUN = "bevel"

    @property
    def across(self) -> bool:
        """Whether l is drawn across an edge of f (no crease c -> c')."""
        return self.opposite is None

    def version_needed(self) -> tuple[int, str, str]:
        for key, used in (
            ("corner", self.across),  # no `opposite` to name: its corner on the edge
            ("edges", self.edges is not EdgeSet.DRAWN),
            ("radius", self.radius is not None),
            ("distances", self.distances is not None),
        ):
            if used:
                why = "across an edge" if key == "corner" else f"`{key}`"
                return 3, key, f"a bevel {why} needs version 3 (versions 1 and 2 have no rounds)"
        return super().version_needed()

    @property
    def regular(self) -> bool:
        """Whether the step is a fillet or a chamfer rather than the freeform l."""
        return self.radius is not None or self.distances is not None

    @property
    def is_round(self) -> bool:
        """Whether the step is more than the paper's freeform cut along one crease: across
        an edge, a fillet or chamfer, or along more than the drawn edge."""
        return self.across or self.regular or self.edges is not EdgeSet.DRAWN

    @property
    def name(self) -> str:
        return "fillet" if self.radius is not None else "chamfer" if self.distances else "bevel"

    def check(self) -> None:
        if self.radius is not None and self.distances is not None:
            raise OperationError("bevel: give a fillet radius or chamfer distances, not both")
        if self.radius is not None and not (math.isfinite(self.radius) and self.radius > 0):
            raise OperationError(f"bevel: fillet radius must be positive, got {self.radius}")
        if self.distances is not None and not all(
            math.isfinite(d) and d > 0 for d in self.distances
        ):
            raise OperationError(
                f"bevel: chamfer distances must be positive, got {list(self.distances)}"
            )
        if self.edges is EdgeSet.OUTLINE and not self.across:
            raise OperationError(
                "bevel: edges = outline rounds the outline of f, which needs l drawn across "
                "an edge of f (no opposite corner c')"
            )

    def describe(self) -> str:
        where = "across" if self.across else f"c'={_fmt(self.opposite)}"
        shape = (
            f" r={_num(self.radius)}"
            if self.radius is not None
            else f" d={_num(self.distances[0])},{_num(self.distances[1])}"
            if self.distances
            else ""
        )
        edges = "" if self.edges is EdgeSet.DRAWN else f" edges={self.edges.value}"
        return (
            f"Bevel {self.face.describe()} c={_fmt(self.corner)} {where} "
            f"l=Bezier[{', '.join(_fmt(p) for p in self.profile)}]{edges}{shape}"
        )

    def parameters(self) -> dict[str, Any]:
        out: dict[str, Any] = {"corner": list(self.corner)}
        if self.opposite is not None:
            out["opposite"] = list(self.opposite)
        out["profile"] = [list(p) for p in self.profile]
        if self.edges is not EdgeSet.DRAWN:
            out["edges"] = self.edges.value
        if self.radius is not None:
            out["radius"] = self.radius
        if self.distances is not None:
            out["distances"] = list(self.distances)
        return out

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> Bevel:
        edges = EdgeSet.DRAWN
        if "edges" in o:
            try:
                edges = EdgeSet(o["edges"])
            except ValueError:
                raise _fail(
                    f"{path}.edges", f"expected one of {[e.value for e in EdgeSet]}", o["edges"]
                ) from None
        if "radius" in o and "distances" in o:
            raise _fail(f"{path}.distances", "a fillet radius is given already", o["distances"])
        if edges is EdgeSet.OUTLINE and "opposite" in o:
            raise _fail(
                f"{path}.edges",
                "the outline of f needs l drawn across an edge of f (leave out 'opposite')",
                o["edges"],
            )
        return cls(
            face,
            vec(o["corner"], f"{path}.corner"),
            vec(o["opposite"], f"{path}.opposite") if "opposite" in o else None,
            points(o["profile"], f"{path}.profile", 4, 4),
            edges,
            number(o["radius"], f"{path}.radius", positive=True) if "radius" in o else None,
            _distances(o["distances"], f"{path}.distances") if "distances" in o else None,
        )

    def reflected(self, point: PointMap, vector: PointMap) -> Bevel:
        return dataclasses.replace(
            self,
            face=self.face.reflected(point, vector),
            corner=point(self.corner),
            opposite=None if self.opposite is None else point(self.opposite),
            profile=tuple(point(p) for p in self.profile),
        )


def _distances(v: Any, path: str) -> tuple[float, float]:
    if not isinstance(v, list) or len(v) != 2:
        raise _fail(path, "expected [d1, d2], two positive numbers", v)
    return (number(v[0], f"{path}[0]", positive=True), number(v[1], f"{path}[1]", positive=True))


class _CombinedOperation(_Operation):
    """An operation whose primitive combines with the solid by its `mode` (prism, sweep)."""

    mode: Mode

    @property
    def boolean(self) -> Mode:
        return self.mode

    @property
    def name(self) -> str:
        return f"{self.mode.value} {self.NOUN}"


@dataclass(frozen=True)
class AddSubPrism(_CombinedOperation):
    """A right prism on face f: base polygon c (3-6 vertices on f's plane), length d > 0.

    The prism goes outwards along n_f for ADD/INTERSECT/REPLACE and inwards for SUBTRACT.
    """

    face: FaceRef
    polygon: tuple[Vec3, ...]
    d: float
    mode: Mode = Mode.ADD

    type = OperatorType.ADDSUB
    KEYS = ("polygon", "d", "mode")
    NOUN = "prism"
    NAMES: ClassVar[dict[Mode, str]] = {
        Mode.ADD: "AddPolyhedron",
        Mode.SUBTRACT: "SubtractPolyhedron",
        Mode.INTERSECT: "IntersectPolyhedron",
        Mode.REPLACE: "ReplaceByPolyhedron",
    }

    def check(self) -> None:
        if not 3 <= len(self.polygon) <= 6:
            raise OperationError(
                f"prism: base polygon c needs 3 to 6 vertices, got {len(self.polygon)}"
            )
        if not self.d > 0:
            raise OperationError(f"prism: length d must be positive, got {self.d}")

    def describe(self) -> str:
        return (
            f"{self.NAMES[self.mode]} {self.face.describe()} c={len(self.polygon)}-gon"
            f"[{', '.join(_fmt(p) for p in self.polygon)}] d={_num(self.d)}"
        )

    def parameters(self) -> dict[str, Any]:
        return {"polygon": [list(p) for p in self.polygon], "d": self.d, "mode": self.mode.value}

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> AddSubPrism:
        return cls(
            face,
            points(o["polygon"], f"{path}.polygon", 3, 6),
            number(o["d"], f"{path}.d", positive=True),
            _mode(o["mode"], f"{path}.mode"),
        )

    def reflected(self, point: PointMap, vector: PointMap) -> AddSubPrism:
        """Mirrored, with the polygon's vertex order reversed so that it keeps its
        orientation on the mirrored face."""
        return AddSubPrism(
            self.face.reflected(point, vector),
            tuple(point(p) for p in reversed(self.polygon)),
            self.d,
            self.mode,
        )


@dataclass(frozen=True)
class Sweep(_CombinedOperation):
    """A swept solid of revolution standing on face f.

    c0 is the circle of radius r0 centred at `center` on f's plane; c1 is the circle
    of radius r1 whose centre is d mm away along the primitive's direction (outwards
    along n_f, inwards for SUBTRACT). The profile c_p is a cubic Bezier from c0 to c1
    in a plane through the axis; `profile` holds its two inner control points as
    (r, h): distance from the axis and height above c0's plane, in mm. Its end
    points are (r0, 0) and (r1, d).
    """

    face: FaceRef
    center: Vec3
    r0: float
    r1: float
    d: float
    profile: tuple[Vec2, Vec2]
    mode: Mode = Mode.ADD

    type = OperatorType.SWEEP
    KEYS = ("center", "r0", "r1", "d", "profile", "mode")
    NOUN = "sweep"
    NAMES: ClassVar[dict[Mode, str]] = {
        Mode.ADD: "AddSweepShape",
        Mode.SUBTRACT: "SubtractSweepShape",
        Mode.INTERSECT: "IntersectSweepShape",
        Mode.REPLACE: "ReplaceBySweepShape",
    }

    def check(self) -> None:
        if not (self.r0 > 0 and self.r1 > 0 and self.d > 0):
            raise OperationError(
                f"sweep: r0, r1 and d must be positive, got r0={self.r0}, r1={self.r1}, d={self.d}"
            )
        rh = bezier(np.array(self.control_points(), dtype=float), np.linspace(0, 1, 257))
        if rh[:, 0].min() <= 0:
            raise OperationError("sweep: profile c_p crosses the axis (a radius <= 0)")
        fall = np.diff(rh[:, 1])
        if fall.min() < -1e-9 * self.d:
            at = rh[int(np.argmin(fall)), 1]
            raise OperationError(
                f"sweep: profile c_p folds back (its height h goes down near h = {at:.4g} on "
                f"the way from 0 to d = {_num(self.d)}), so the swept surface would cross "
                "itself; move the profile's control points so that h only rises"
            )

    def describe(self) -> str:
        ctrl = ", ".join(_fmt(p) for p in self.control_points())
        return (
            f"{self.NAMES[self.mode]} {self.face.describe()} c0=(center "
            f"{_fmt(self.center)}, r {_num(self.r0)}) c1=(r {_num(self.r1)}, offset "
            f"{_num(self.d)}) c_p=Bezier(r,h)[{ctrl}]"
        )

    def parameters(self) -> dict[str, Any]:
        return {
            "center": list(self.center),
            "r0": self.r0,
            "r1": self.r1,
            "d": self.d,
            "profile": [list(p) for p in self.profile],
            "mode": self.mode.value,
        }

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> Sweep:
        return cls(
            face,
            vec(o["center"], f"{path}.center"),
            number(o["r0"], f"{path}.r0", positive=True),
            number(o["r1"], f"{path}.r1", positive=True),
            number(o["d"], f"{path}.d", positive=True),
            points(o["profile"], f"{path}.profile", 2, 2, dim=2),
            _mode(o["mode"], f"{path}.mode"),
        )

    def reflected(self, point: PointMap, vector: PointMap) -> Sweep:
        return Sweep(
            self.face.reflected(point, vector),
            point(self.center),
            self.r0,
            self.r1,
            self.d,
            self.profile,
            self.mode,
        )

    def control_points(self) -> tuple[Vec2, Vec2, Vec2, Vec2]:
        """All four (r, h) control points of c_p."""
        return ((self.r0, 0.0), self.profile[0], self.profile[1], (self.r1, self.d))

    def retuned(
        self, r0: float | None = None, r1: float | None = None, d: float | None = None
    ) -> Sweep:
        """The same sweep with new r0, r1 or d; the inner control points follow
        (`retuned_profile`)."""
        new = (
            self.r0 if r0 is None else r0,
            self.r1 if r1 is None else r1,
            self.d if d is None else d,
        )
        return Sweep(
            self.face,
            self.center,
            *new,
            retuned_profile(self.profile, (self.r0, self.r1, self.d), new),
            self.mode,
        )


@dataclass(frozen=True)
class Shell(_Operation):
    """The solid hollowed out, open at face f, with walls t > 0 mm thick (beyond the paper).

    Every face but f is offset inwards by t (OCCT's thick solid, as cadquery's shell
    inwards and PartDesign's Thickness build it), so f becomes a rim t wide around the
    opening. f is stored as every base face is and followed the same way on replay.
    """

    face: FaceRef
    t: float

    type = OperatorType.SHELL
    KEYS = ("t",)
    NOUN = "shell"

    @property
    def boolean(self) -> Mode:
        """The hollowed solid replaces the solid (`brep/operators.shell_tool` builds it)."""
        return Mode.REPLACE

    def check(self) -> None:
        if not (self.t > 0 and math.isfinite(self.t)):
            raise OperationError(f"shell: wall thickness t must be positive, got {self.t}")

    def describe(self) -> str:
        return f"Shell {self.face.describe()} t={_num(self.t)}"

    def version_needed(self) -> tuple[int, str, str]:
        return 3, "type", "a shell needs version 3 (versions 1 and 2 have no shell)"

    def parameters(self) -> dict[str, Any]:
        return {"t": self.t}

    @classmethod
    def parse(cls, face: FaceRef, o: dict, path: str) -> Shell:
        return cls(face, number(o["t"], f"{path}.t", positive=True))

    def reflected(self, point: PointMap, vector: PointMap) -> Shell:
        return Shell(self.face.reflected(point, vector), self.t)


def straight_profile(r0: float, r1: float, d: float) -> tuple[Vec2, Vec2]:
    """A sweep's inner (r, h) control points for a straight profile from (r0, 0) to
    (r1, d): the line's thirds (a cone, or a cylinder)."""
    return (
        (float(r0 + (r1 - r0) / 3), float(d / 3)),
        (float(r0 + 2 * (r1 - r0) / 3), float(2 * d / 3)),
    )


def retuned_profile(profile: tuple[Vec2, Vec2], old: Vec3, new: Vec3) -> tuple[Vec2, Vec2]:
    """A sweep's inner (r, h) control points after its (r0, r1, d) change from `old` to
    `new`.

    As in the paper's parameter tuning, each control point keeps its relative position:
    its height scales with d, and its radius is re-interpolated between the (scaled) end
    radii in proportion to where it sat before.
    """
    (r0, r1, d), (nr0, nr1, nd) = old, new
    pts = []
    for r, h in profile:
        t = h / d if d else 0.0
        old_axis = r0 + (r1 - r0) * t
        new_axis = nr0 + (nr1 - nr0) * t
        scale = new_axis / old_axis if old_axis > 0 else 1.0
        pts.append((r * scale, h * nd / d if d else h))
    return (pts[0], pts[1])


Operation = Extrude | Bevel | AddSubPrism | Sweep | Shell
# The operation dataclass of each operator.
OPERATIONS: dict[OperatorType, type] = per_operator(
    {
        OperatorType.EXTRUDE: Extrude,
        OperatorType.BEVEL: Bevel,
        OperatorType.ADDSUB: AddSubPrism,
        OperatorType.SWEEP: Sweep,
        OperatorType.SHELL: Shell,
    },
    "OPERATIONS",
)


@dataclass(frozen=True)
class Protocol:
    """A base box and the operations applied to it in order."""

    base: Box
    operations: tuple[Operation, ...] = field(default_factory=tuple)

    def append(self, op: Operation) -> Protocol:
        return Protocol(self.base, self.operations + (op,))

    def to_json(self) -> str:
        """Standard JSON (NaN and infinities are refused: `loads` could not read them)."""
        try:
            return json.dumps(protocol_to_dict(self), indent=1, allow_nan=False)
        except ValueError:
            raise ProtocolError("a parameter is NaN or infinite; nothing was written") from None

    def save(self, path: str | Path) -> None:
        """Write the protocol as JSON, only if `load` accepts what would be written (the
        loader's own rules); the file is replaced only once fully written.

        Raises:
            ProtocolError: naming the field the loader refuses; the file is untouched.
        """
        write_atomically(path, self.file_text())

    def file_text(self) -> str:
        """The text `save` writes, checked to be what `load` accepts.

        Raises:
            ProtocolError: naming the field the loader refuses.
        """
        text = self.to_json() + "\n"
        loads(text, "the protocol to save")
        return text

    def listing(self) -> str:
        """A readable listing, one line per step, like the paper's protocol figures."""
        lines = [f"0  Box {_fmt(self.base.size)} mm"]
        lines += [f"{i}  {op.describe()}" for i, op in enumerate(self.operations, 1)]
        return "\n".join(lines)


def describe(op: Operation) -> str:
    """One line naming the operator and its parameters with the paper's symbols."""
    return op.describe()


# ----------------------------------------------------------------- JSON


def operation_to_dict(op: Operation) -> dict[str, Any]:
    return op.to_dict()


def protocol_version(p: Protocol) -> int:
    """The lowest schema version that holds `p` (each operation's `version_needed`): 3
    with a shell or a round (a bevel across an edge, along a chain or an outline, a
    fillet or a chamfer), else 2 when a base face is curved, else 1."""
    return max((op.version_needed()[0] for op in p.operations), default=1)


def protocol_to_dict(p: Protocol) -> dict[str, Any]:
    return {
        "format": FORMAT,
        "version": protocol_version(p),
        "units": "mm",
        "base": {"type": "box", "size": list(p.base.size)},
        "operations": [op.to_dict() for op in p.operations],
    }


_KINDS = {t.value: cls for t, cls in OPERATIONS.items()}


def operation_from_dict(v: Any, path: str = "operation") -> Operation:
    """Parse one operation; raise ProtocolError naming the field and value on any flaw."""
    try:
        return _operation(v, path)
    except FieldError as e:
        raise e if isinstance(e, ProtocolError) else ProtocolError(str(e)) from None


def _operation(v: Any, path: str) -> Operation:
    if not isinstance(v, dict):
        raise _fail(path, "expected an object", v)
    kind = v.get("type")
    if not isinstance(kind, str) or kind not in _KINDS:
        raise _fail(f"{path}.type", f"expected one of {sorted(_KINDS)}", kind)
    cls = _KINDS[kind]
    optional = set(cls.OPTIONAL)
    o = obj(v, path, {"type", "face", *cls.KEYS} - optional, optional)
    return cls.parse(FaceRef.from_dict(o["face"], f"{path}.face"), o, path)


def protocol_from_dict(v: Any) -> Protocol:
    """Parse a whole protocol; nothing is returned unless every field is valid."""
    try:
        return _protocol(v)
    except FieldError as e:
        raise e if isinstance(e, ProtocolError) else ProtocolError(str(e)) from None


def _protocol(v: Any) -> Protocol:
    o = obj(v, "protocol", {"format", "version", "units", "base", "operations"})
    header(o, FORMAT, VERSIONS)
    size = box_size(o["base"])
    ops = o["operations"]
    if not isinstance(ops, list):
        raise _fail("operations", "expected a list", ops)
    parsed = tuple(_operation(op, f"operations[{i}]") for i, op in enumerate(ops))
    for i, op in enumerate(parsed):
        version, key, why = op.version_needed()
        if version > o["version"]:
            value = ops[i]
            for part in key.split("."):
                value = value[part]
            raise _fail(f"operations[{i}].{key}", why, value)
    return Protocol(Box(size), parsed)


def loads(text: str, source: str = "<string>") -> Protocol:
    """Parse protocol JSON text; errors are prefixed with `source`."""
    data = parse_json(text, source, ProtocolError, "protocol")
    try:
        return protocol_from_dict(data)
    except ProtocolError as e:
        raise ProtocolError(f"{source}: {e}") from None


def load(path: str | Path) -> Protocol:
    """Read and validate a protocol file."""
    path = Path(path)
    try:
        text = read_capped(path).decode()
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ProtocolError(f"{path}: cannot read protocol file: {e}") from None
    return loads(text, str(path))
