# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sketch session files: a base box and the steps a designer sketched, with their views.

JSON schema, version 1::

    {"format": "sketch2cad-session", "version": 1, "units": "mm",
     "base": {"type": "box", "size": [lx, ly, lz]},
     "steps": [
       {"camera": {"center": P, "direction": P, "up": P, "scale": float,
                   "width": int, "height": int},
        "strokes": [[[x, y], [x, y], ...], ...],       # pixels, x right, y down
        "choices": {"option": null | MODE,              # optional; force the Boolean
                    "symmetry": null | "x" | "y" | "z", # mirror through that mid-plane
                    "regularize": true,                 # snapping and rectification
                    "snap_step": 0.0,                   # optional: the length grid (mm)
                    "snap_px": 5.0,                     # optional: the least snap tolerance
                    "skip_snaps": ["position", ...],    # optional: the snaps undone
                    "edges": "drawn"}}]}                # optional: a bevel's edges

Each step's strokes are in its camera's pixels (render/camera.py's convention); the
camera is the orthographic view the designer sketched in. The optional choices
(InterpretOptions' fields) are written only when they differ from their defaults, so a
step without them reads, and is written, as before they existed.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..brep.fields import (
    MAX_BOX_MM,
    FieldError,
    box_size,
    error,
    header,
    number,
    obj,
    parse_json,
    vec,
)
from ..brep.files import read_capped, write_atomically
from ..brep.protocol import Box, EdgeSet, Mode, ProtocolError
from ..render.camera import OrthoCamera
from .fitting.regularize import SNAP_KINDS
from .options import InterpretOptions

FORMAT = "sketch2cad-session"
VERSION = 1
SYMMETRY_PLANES = ("x", "y", "z")
DEFAULTS = InterpretOptions()
# Largest grid step and snap tolerance a session may ask for: beyond them snapping would
# move what the designer drew, not the hand's error.
MAX_SNAP_STEP, MAX_SNAP_PX = 100.0, 100.0
# Where a view may be: its centre within MAX_VIEW_MM of the origin on each axis, its half
# height from MIN_SCALE_MM to MAX_VIEW_MM, strokes within MAX_VIEW_MM pixels of the image.
# Ten times the largest base box; beyond them the arithmetic of the maps overflows.
MAX_VIEW_MM, MIN_SCALE_MM = 10 * MAX_BOX_MM, 1e-4


class SessionError(ProtocolError):
    """A session file or value is malformed; the message names the field and value."""


@dataclass
class SketchStep:
    """One sketched step: the view and the strokes (each a (K, 2) pixel polyline)."""

    camera: OrthoCamera
    strokes: list[np.ndarray]
    choices: InterpretOptions = field(default_factory=InterpretOptions)


@dataclass
class Session:
    """A base box and the sketched steps, in order."""

    base: Box
    steps: list[SketchStep]

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "version": VERSION,
            "units": "mm",
            "base": {"type": "box", "size": list(self.base.size)},
            "steps": [_step_dict(s) for s in self.steps],
        }

    def save(self, path: str | Path) -> None:
        """Write the session as JSON; the file is replaced only once fully written."""
        write_atomically(path, json.dumps(self.to_dict()) + "\n")


def _step_dict(s: SketchStep) -> dict[str, Any]:
    return {
        "camera": s.camera.to_dict(),
        "strokes": [[[round(float(x), 3), round(float(y), 3)] for x, y in st] for st in s.strokes],
        "choices": _choices_dict(s.choices),
    }


def _choices_dict(c: InterpretOptions) -> dict[str, Any]:
    out = {
        "option": c.option.value if c.option else None,
        "symmetry": c.symmetry,
        "regularize": c.regularize,
    }
    if c.snap_step != DEFAULTS.snap_step:
        out["snap_step"] = float(c.snap_step)
    if c.snap_px != DEFAULTS.snap_px:
        out["snap_px"] = float(c.snap_px)
    if c.skip_snaps:
        out["skip_snaps"] = sorted(c.skip_snaps)
    if c.edges is not DEFAULTS.edges:
        out["edges"] = c.edges.value
    return out


def step_to_dict(step: SketchStep) -> dict[str, Any]:
    """One step as it is written in a session file (the FreeCAD features keep theirs)."""
    return _step_dict(step)


def step_from_dict(v: Any, path: str = "step") -> SketchStep:
    """Parse one step of a session file; errors name the field and value."""
    try:
        return _step(v, path)
    except FieldError as e:
        raise e if isinstance(e, SessionError) else SessionError(str(e)) from None


# ----------------------------------------------------------------- loading


def _err(path: str, msg: str, value: Any) -> SessionError:
    return SessionError(str(error(path, msg, value)))


def camera_from_dict(v: Any, path: str) -> OrthoCamera:
    o = obj(v, path, {"center", "direction", "up", "scale", "width", "height"})
    for k in ("width", "height"):
        if isinstance(o[k], bool) or not isinstance(o[k], int) or not 16 <= o[k] <= 8192:
            raise _err(f"{path}.{k}", "expected an integer from 16 to 8192", o[k])
    try:
        for k, n in (("center", 3), ("direction", 3), ("up", 3)):
            vec(o[k], f"{path}.{k}", n)
        center, scale = o["center"], number(o["scale"], f"{path}.scale")
        if max(map(abs, center)) > MAX_VIEW_MM:
            raise _err(
                f"{path}.center", f"expected coordinates within +-{MAX_VIEW_MM:g} mm", center
            )
        if scale > 0 and not MIN_SCALE_MM <= scale <= MAX_VIEW_MM:
            raise _err(
                f"{path}.scale", f"expected from {MIN_SCALE_MM:g} to {MAX_VIEW_MM:g} mm", scale
            )
        return OrthoCamera.from_dict(o)
    except FieldError as e:  # already names the field
        raise SessionError(str(e)) from None
    except ValueError as e:
        raise SessionError(f"{path}: {e}") from None


def _choices(v: Any, path: str) -> InterpretOptions:
    o = obj(
        v,
        path,
        set(),
        {"option", "symmetry", "regularize", "snap_step", "snap_px", "skip_snaps", "edges"},
    )
    option = o.get("option")
    if option is not None:
        try:
            option = Mode(option)
        except ValueError:
            raise _err(
                f"{path}.option", f"expected null or one of {[m.value for m in Mode]}", option
            ) from None
    sym = o.get("symmetry")
    if sym is not None and sym not in SYMMETRY_PLANES:
        raise _err(f"{path}.symmetry", f"expected null or one of {list(SYMMETRY_PLANES)}", sym)
    reg = o.get("regularize", True)
    if not isinstance(reg, bool):
        raise _err(f"{path}.regularize", "expected true or false", reg)
    step = number(o.get("snap_step", DEFAULTS.snap_step), f"{path}.snap_step")
    if not 0 <= step <= MAX_SNAP_STEP:
        raise _err(
            f"{path}.snap_step", f"expected a grid step from 0 (none) to {MAX_SNAP_STEP} mm", step
        )
    px = number(o.get("snap_px", DEFAULTS.snap_px), f"{path}.snap_px")
    if not 0 < px <= MAX_SNAP_PX:
        raise _err(
            f"{path}.snap_px", f"expected a tolerance above 0 and at most {MAX_SNAP_PX} px", px
        )
    skip = o.get("skip_snaps", [])
    if not isinstance(skip, list) or not all(isinstance(k, str) and k in SNAP_KINDS for k in skip):
        raise _err(
            f"{path}.skip_snaps", f"expected a list of snap kinds from {list(SNAP_KINDS)}", skip
        )
    edges = o.get("edges", DEFAULTS.edges.value)
    if edges not in [e.value for e in EdgeSet]:
        raise _err(f"{path}.edges", f"expected one of {[e.value for e in EdgeSet]}", edges)
    return InterpretOptions(
        reg, option, sym, float(step), float(px), frozenset(skip), edges=EdgeSet(edges)
    )


def _step(v: Any, path: str) -> SketchStep:
    o = obj(v, path, {"camera", "strokes"}, {"choices"})
    cam = camera_from_dict(o["camera"], f"{path}.camera")
    strokes = o["strokes"]
    if not isinstance(strokes, list) or not strokes:
        raise _err(f"{path}.strokes", "expected a non-empty list of strokes", strokes)
    out = []
    for i, s in enumerate(strokes):
        if not isinstance(s, list) or len(s) < 2:
            raise _err(f"{path}.strokes[{i}]", "expected a list of at least 2 points", s)
        pts = np.array([vec(p, f"{path}.strokes[{i}][{j}]", 2) for j, p in enumerate(s)])
        if np.abs(pts).max() > MAX_VIEW_MM:
            raise _err(
                f"{path}.strokes[{i}]", f"expected pixels within +-{MAX_VIEW_MM:g} of the image", s
            )
        out.append(pts)
    return SketchStep(cam, out, _choices(o.get("choices", {}), f"{path}.choices"))


def session_from_dict(v: Any) -> Session:
    """Parse a whole session; nothing is returned unless every field is valid."""
    try:
        return _session(v)
    except FieldError as e:
        raise e if isinstance(e, SessionError) else SessionError(str(e)) from None


def _session(v: Any) -> Session:
    o = obj(v, "session", {"format", "version", "units", "base", "steps"})
    header(o, FORMAT, VERSION)
    size = box_size(o["base"])
    if not isinstance(o["steps"], list):
        raise _err("steps", "expected a list", o["steps"])
    return Session(Box(size), [_step(s, f"steps[{i}]") for i, s in enumerate(o["steps"])])


def load_session(path: str | Path) -> Session:
    """Read and validate a session file; errors name the file, the field and the value."""
    path = Path(path)
    try:
        text = read_capped(path).decode()
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise SessionError(f"{path}: cannot read session file: {e}") from None
    data = parse_json(text, str(path), SessionError, "session")
    try:
        return session_from_dict(data)
    except SessionError as e:
        raise SessionError(f"{path}: {e}") from None
