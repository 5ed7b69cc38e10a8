# SPDX-License-Identifier: LGPL-2.1-or-later
"""The protocol: typed operations with the paper's parameters, and its versioned JSON.

A protocol is a base box followed by operations applied in order (paper, "Protocols
for CAD modeling"). All lengths are in millimetres, all points and vectors in the
model's world frame. A base face is stored geometrically (`FaceRef`: a point inside
the face and its outward normal), never as a face index, so that replay resolves it
against whatever solid the earlier steps produced.

JSON schema, version 1 (every key required unless marked optional)::

    {"format": "sketch2cad-protocol", "version": 1, "units": "mm",
     "base": {"type": "box", "size": [lx, ly, lz]},          # centred on the origin
     "operations": [
       {"type": "extrude", "face": FACE, "d": float},
       {"type": "bevel", "face": FACE, "corner": P, "opposite": P,
        "profile": [P, P, P, P]},                              # cubic Bezier on f
       {"type": "addsub", "face": FACE, "polygon": [P, P, P, ...],   # 3 to 6 points
        "d": float, "mode": MODE},
       {"type": "sweep", "face": FACE, "center": P, "r0": float, "r1": float,
        "d": float, "profile": [[r, h], [r, h]], "mode": MODE}]}
    FACE = {"point": P, "normal": P}; P = [x, y, z]
    MODE = "add" | "subtract" | "intersect" | "replace"

`validate` style: every loader error names the field path and the offending value.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any, Union

from .fields import FieldError, box_size, error, header, number, obj, points, vec
from .files import write_atomically

FORMAT = "sketch2cad-protocol"
VERSION = 1

Vec3 = tuple[float, float, float]
Vec2 = tuple[float, float]


class OperatorType(Enum):
    """The four operators of the paper; also the classifier's class order."""

    EXTRUDE = "extrude"
    BEVEL = "bevel"
    ADDSUB = "addsub"
    SWEEP = "sweep"


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


class ProtocolError(FieldError):
    """A protocol file or value is malformed; the message names the field and value."""


@dataclass(frozen=True)
class FaceRef:
    """A planar base face f: a point inside it and its outward unit normal (world, mm)."""

    point: Vec3
    normal: Vec3


@dataclass(frozen=True)
class Box:
    """The base shape: an axis-aligned box of size (lx, ly, lz) mm centred on the origin."""

    size: Vec3


@dataclass(frozen=True)
class Extrude:
    """Move face f along its outward normal by d mm (d > 0 pads, d < 0 pockets)."""

    face: FaceRef
    d: float

    type = OperatorType.EXTRUDE


@dataclass(frozen=True)
class Bevel:
    """Round corner c of face f with profile l, along the crease from c to c'.

    `corner` is c (a vertex of f), `opposite` is c' (the other end of the crease,
    so c' - c points into the solid along -n_f), `profile` is l, the four control
    points of a cubic Bezier on f's plane from one edge of f at c to the other.
    """

    face: FaceRef
    corner: Vec3
    opposite: Vec3
    profile: tuple[Vec3, Vec3, Vec3, Vec3]

    type = OperatorType.BEVEL


@dataclass(frozen=True)
class AddSubPrism:
    """A right prism on face f: base polygon c (3-6 vertices on f's plane), length d > 0.

    The prism goes outwards along n_f for ADD/INTERSECT/REPLACE and inwards for SUBTRACT.
    """

    face: FaceRef
    polygon: tuple[Vec3, ...]
    d: float
    mode: Mode = Mode.ADD

    type = OperatorType.ADDSUB


@dataclass(frozen=True)
class Sweep:
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

    def control_points(self) -> tuple[Vec2, Vec2, Vec2, Vec2]:
        """All four (r, h) control points of c_p."""
        return ((self.r0, 0.0), self.profile[0], self.profile[1], (self.r1, self.d))

    def retuned(self, r0: float | None = None, r1: float | None = None,
                d: float | None = None) -> "Sweep":
        """The same sweep with new r0, r1 or d; the inner control points follow.

        As in the paper's parameter tuning, each control point keeps its relative
        position: its height scales with d, and its radius is re-interpolated
        between the (scaled) end radii in proportion to where it sat before.
        """
        nr0 = self.r0 if r0 is None else r0
        nr1 = self.r1 if r1 is None else r1
        nd = self.d if d is None else d
        pts = []
        for r, h in self.profile:
            t = h / self.d if self.d else 0.0
            old_axis = self.r0 + (self.r1 - self.r0) * t
            new_axis = nr0 + (nr1 - nr0) * t
            scale = new_axis / old_axis if old_axis > 0 else 1.0
            pts.append((r * scale, h * nd / self.d if self.d else h))
        return Sweep(self.face, self.center, nr0, nr1, nd, (pts[0], pts[1]), self.mode)


Operation = Union[Extrude, Bevel, AddSubPrism, Sweep]


@dataclass(frozen=True)
class Protocol:
    """A base box and the operations applied to it in order."""

    base: Box
    operations: tuple[Operation, ...] = field(default_factory=tuple)

    def append(self, op: Operation) -> "Protocol":
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
        text = self.to_json() + "\n"
        loads(text, "the protocol to save")
        write_atomically(path, text)

    def listing(self) -> str:
        """A readable listing, one line per step, like the paper's protocol figures."""
        lines = [f"0  Box {_fmt(self.base.size)} mm"]
        lines += [f"{i}  {describe(op)}" for i, op in enumerate(self.operations, 1)]
        return "\n".join(lines)


# ----------------------------------------------------------------- description

_MODE_NAMES = {
    OperatorType.ADDSUB: {Mode.ADD: "AddPolyhedron", Mode.SUBTRACT: "SubtractPolyhedron",
                          Mode.INTERSECT: "IntersectPolyhedron",
                          Mode.REPLACE: "ReplaceByPolyhedron"},
    OperatorType.SWEEP: {Mode.ADD: "AddSweepShape", Mode.SUBTRACT: "SubtractSweepShape",
                         Mode.INTERSECT: "IntersectSweepShape",
                         Mode.REPLACE: "ReplaceBySweepShape"},
}


def _num(x: float) -> str:
    # to the micrometre (mm units), and no "-0" or "1e-15" from round-off
    return f"{round(x, 3) + 0.0:g}"


def _fmt(v) -> str:
    return "(" + ", ".join(_num(x) for x in v) + ")"


def _face(f: FaceRef) -> str:
    return f"f[n={_fmt(f.normal)} at {_fmt(f.point)}]"


def describe(op: Operation) -> str:
    """One line naming the operator and its parameters with the paper's symbols."""
    if isinstance(op, Extrude):
        return f"Extrude {_face(op.face)} d={_num(op.d)}"
    if isinstance(op, Bevel):
        return (f"Bevel {_face(op.face)} c={_fmt(op.corner)} c'={_fmt(op.opposite)} "
                f"l=Bezier[{', '.join(_fmt(p) for p in op.profile)}]")
    if isinstance(op, AddSubPrism):
        name = _MODE_NAMES[OperatorType.ADDSUB][op.mode]
        return (f"{name} {_face(op.face)} c={len(op.polygon)}-gon"
                f"[{', '.join(_fmt(p) for p in op.polygon)}] d={_num(op.d)}")
    name = _MODE_NAMES[OperatorType.SWEEP][op.mode]
    return (f"{name} {_face(op.face)} c0=(center {_fmt(op.center)}, r {_num(op.r0)}) "
            f"c1=(r {_num(op.r1)}, offset {_num(op.d)}) "
            f"c_p=Bezier(r,h)[{', '.join(_fmt(p) for p in op.control_points())}]")


# ----------------------------------------------------------------- to JSON

def _face_dict(f: FaceRef) -> dict:
    return {"point": list(f.point), "normal": list(f.normal)}


def operation_to_dict(op: Operation) -> dict[str, Any]:
    d: dict[str, Any] = {"type": op.type.value, "face": _face_dict(op.face)}
    if isinstance(op, Extrude):
        d["d"] = op.d
    elif isinstance(op, Bevel):
        d.update(corner=list(op.corner), opposite=list(op.opposite),
                 profile=[list(p) for p in op.profile])
    elif isinstance(op, AddSubPrism):
        d.update(polygon=[list(p) for p in op.polygon], d=op.d, mode=op.mode.value)
    else:
        d.update(center=list(op.center), r0=op.r0, r1=op.r1, d=op.d,
                 profile=[list(p) for p in op.profile], mode=op.mode.value)
    return d


def protocol_to_dict(p: Protocol) -> dict[str, Any]:
    return {"format": FORMAT, "version": VERSION, "units": "mm",
            "base": {"type": "box", "size": list(p.base.size)},
            "operations": [operation_to_dict(op) for op in p.operations]}


# ----------------------------------------------------------------- from JSON

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


def _face_ref(v: Any, path: str) -> FaceRef:
    o = obj(v, path, {"point", "normal"})
    return FaceRef(vec(o["point"], f"{path}.point"), _unit(o["normal"], f"{path}.normal"))


_KEYS = {
    "extrude": {"type", "face", "d"},
    "bevel": {"type", "face", "corner", "opposite", "profile"},
    "addsub": {"type", "face", "polygon", "d", "mode"},
    "sweep": {"type", "face", "center", "r0", "r1", "d", "profile", "mode"},
}


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
    if not isinstance(kind, str) or kind not in _KEYS:
        raise _fail(f"{path}.type", f"expected one of {sorted(_KEYS)}", kind)
    o = obj(v, path, _KEYS[kind])
    face = _face_ref(o["face"], f"{path}.face")
    if kind == "extrude":
        return Extrude(face, number(o["d"], f"{path}.d", nonzero=True))
    if kind == "bevel":
        return Bevel(face, vec(o["corner"], f"{path}.corner"),
                     vec(o["opposite"], f"{path}.opposite"),
                     points(o["profile"], f"{path}.profile", 4, 4))
    if kind == "addsub":
        return AddSubPrism(face, points(o["polygon"], f"{path}.polygon", 3, 6),
                           number(o["d"], f"{path}.d", positive=True),
                           _mode(o["mode"], f"{path}.mode"))
    return Sweep(face, vec(o["center"], f"{path}.center"),
                 number(o["r0"], f"{path}.r0", positive=True),
                 number(o["r1"], f"{path}.r1", positive=True),
                 number(o["d"], f"{path}.d", positive=True),
                 points(o["profile"], f"{path}.profile", 2, 2, dim=2),
                 _mode(o["mode"], f"{path}.mode"))


def protocol_from_dict(v: Any) -> Protocol:
    """Parse a whole protocol; nothing is returned unless every field is valid."""
    try:
        return _protocol(v)
    except FieldError as e:
        raise e if isinstance(e, ProtocolError) else ProtocolError(str(e)) from None


def _protocol(v: Any) -> Protocol:
    o = obj(v, "protocol", {"format", "version", "units", "base", "operations"})
    header(o, FORMAT, VERSION)
    size = box_size(o["base"])
    ops = o["operations"]
    if not isinstance(ops, list):
        raise _fail("operations", "expected a list", ops)
    return Protocol(Box(size), tuple(_operation(op, f"operations[{i}]")
                                     for i, op in enumerate(ops)))


def loads(text: str, source: str = "<string>") -> Protocol:
    """Parse protocol JSON text; errors are prefixed with `source`."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as e:
        raise ProtocolError(f"{source}: not valid JSON: {e}") from None
    except RecursionError:
        raise ProtocolError(f"{source}: not a protocol: nested too deeply") from None
    except ValueError as e:  # an integer past Python's digit limit
        raise ProtocolError(f"{source}: not a protocol: {e}") from None
    try:
        return protocol_from_dict(data)
    except ProtocolError as e:
        raise ProtocolError(f"{source}: {e}") from None


def load(path: str | Path) -> Protocol:
    """Read and validate a protocol file."""
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise ProtocolError(f"{path}: cannot read protocol file: {e}") from None
    return loads(text, str(path))
