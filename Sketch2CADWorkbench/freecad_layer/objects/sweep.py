# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sweep: the solid of revolution of profile c_p between circles c0 and c1; a Revolution
when it adds, a Groove when it subtracts (as PartDesign names solids of revolution), and
a Hole when what it subtracts is a cylinder (a drilled hole, as PartDesign users read it)."""

import math

from ...brep.protocol import Mode, Sweep, retuned_profile
from ..units import length, point
from .feature import ALL_KINDS, GROUP, CombinedFeature, mm, retype, tup, vec
from .prism import MODE_TIP, MODES

TUNED = ("Radius0", "Radius1", "Offset")
PROFILE = "Profile c_p"
# c_p's two inner control points as (r, h): distance from the axis and height above c0
INNER = (("Control1Radius", "Control1Height"), ("Control2Radius", "Control2Height"))
SWEEP_KINDS = {
    Mode.ADD: "Revolution",
    Mode.SUBTRACT: "Groove",
    Mode.INTERSECT: "RevolutionCommon",
    Mode.REPLACE: "RevolutionOnly",
}
ALL_KINDS.extend(SWEEP_KINDS.values())
DRILLED = "Hole"
# Radii within this share of each other are one cylinder's.
SAME_RADIUS_REL = 1e-3


class SweepFeature(CombinedFeature):
    """Editing Radius0, Radius1 or Offset moves the profile's inner control points in
    proportion (`retuned_profile`), as in the paper's parameter tuning, so the shape keeps
    its character instead of kinking."""

    TYPE = "Sketch2CAD::Sweep"
    OPERATION = Sweep
    LABEL = "Revolution"
    KIND_PROPERTIES = ("Mode", "Radius0", "Radius1")
    KINDS = SWEEP_KINDS

    @classmethod
    def kind_of(cls, op: Sweep) -> str:
        if op.mode is Mode.SUBTRACT and _one_radius(op.r0, op.r1):
            return DRILLED
        return super().kind_of(op)

    def kind(self, obj) -> str:
        if Mode(obj.Mode) is Mode.SUBTRACT and _one_radius(mm(obj.Radius0), mm(obj.Radius1)):
            return DRILLED
        return super().kind(obj)

    def add_operation_properties(self, obj) -> None:
        retype(obj, "Center", "App::PropertyPosition", GROUP, "Centre of c0 on face f")
        for name, tip in (
            ("Radius0", "r0: radius of c0"),
            ("Radius1", "r1: radius of c1"),
            ("Offset", "d: distance from c0's centre to c1's along the axis"),
        ):
            if name not in obj.PropertiesList:
                obj.addProperty("App::PropertyLength", name, GROUP, tip)
        for i, (r, h) in enumerate(INNER, 1):
            if r not in obj.PropertiesList:
                obj.addProperty(
                    "App::PropertyDistance",
                    r,
                    PROFILE,
                    f"c_p: inner control point {i}'s distance from the axis",
                )
                obj.addProperty(
                    "App::PropertyDistance",
                    h,
                    PROFILE,
                    f"c_p: inner control point {i}'s height above c0",
                )
        if "Mode" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Mode", GROUP, MODE_TIP)
            obj.Mode = MODES

    @classmethod
    def reading(cls, op: Sweep) -> str:
        return (
            f"{cls.kind_of(op)} ({op.mode.value}): radius {length(op.r0)} to "
            f"{length(op.r1)} over {length(op.d)}, centred at {point(op.center)} "
            f"{cls.on_face(op.face)}"
        )

    def inner(self, obj) -> tuple:
        """c_p's inner control points as ((r, h), (r, h)) in mm."""
        return tuple((mm(getattr(obj, r)), mm(getattr(obj, h))) for r, h in INNER)

    def set_inner(self, obj, profile) -> None:
        for (r, h), (rv, hv) in zip(INNER, profile, strict=False):
            setattr(obj, r, float(rv))
            setattr(obj, h, float(hv))

    def operation(self, obj) -> Sweep:
        return Sweep(
            self.face(obj),
            tup(obj.Center),
            mm(obj.Radius0),
            mm(obj.Radius1),
            mm(obj.Offset),
            self.inner(obj),
            Mode(obj.Mode),
        )

    def set_operation(self, obj, op: Sweep) -> None:
        self._tuning = True  # these values are a whole operation: nothing to retune
        try:
            super().set_operation(obj, op)
            obj.Center = vec(op.center)
            obj.Radius0, obj.Radius1, obj.Offset = op.r0, op.r1, op.d
            self.set_inner(obj, op.profile)
            obj.Mode = op.mode.value
        finally:
            self._tuning = False
        self._last = (op.r0, op.r1, op.d)

    def onChanged(self, obj, prop):
        super().onChanged(obj, prop)
        if (
            prop not in TUNED
            or getattr(self, "_tuning", False)
            or not all(hasattr(obj, p) for p in TUNED + INNER[1] + ("Mode",))
        ):
            return
        last = getattr(self, "_last", None)
        now = (mm(obj.Radius0), mm(obj.Radius1), mm(obj.Offset))
        # Undo, redo and file loading set the profile themselves.
        if "Restore" in obj.State or obj.Document.Transacting or obj.Document.Restoring:
            self._last = now
            return
        # NaN, inf or 0 typed in: the step goes into error (checks.py, the core), and the
        # profile and `_last` stay as they were, so fixing the value restores the step
        if not _positive(now):
            return
        if last is None or not _positive(last):
            self._last = now
            return
        profile = retuned_profile(self.inner(obj), last, now)
        if not all(math.isfinite(c) for p in profile for c in p):
            return  # near the largest double the profile overflows: keep it
        self._last = now
        self._tuning = True
        try:
            self.set_inner(obj, profile)
        finally:
            self._tuning = False

    def migrate(self, obj) -> None:
        old = None
        if "ProfileInner" in obj.PropertiesList:  # saved by an earlier version: (r, h, 0)s
            old = [(p.x, p.y) for p in obj.ProfileInner]
            obj.removeProperty("ProfileInner")
        self._tuning = True
        try:
            super().migrate(obj)
            if old is not None and len(old) == len(INNER):
                self.set_inner(obj, old)
        finally:
            self._tuning = False
        self._last = (mm(obj.Radius0), mm(obj.Radius1), mm(obj.Offset))


def _one_radius(r0: float, r1: float) -> bool:
    """c0 and c1 have the same radius (SAME_RADIUS_REL): the sweep is a cylinder."""
    return abs(r0 - r1) <= SAME_RADIUS_REL * max(abs(r0), abs(r1))


def _positive(values) -> bool:
    """All values finite and above 0."""
    return all(math.isfinite(v) and v > 0 for v in values)
