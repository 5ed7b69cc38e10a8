# SPDX-License-Identifier: LGPL-2.1-or-later
"""Sweep: the solid of revolution of profile c_p between circles c0 and c1."""
import FreeCAD

from ...brep.protocol import Mode, Sweep, retuned_profile
from .feature import GROUP, OperationFeature, mm, tup, vec
from .prism import MODE_TIP, MODES

TUNED = ("Radius0", "Radius1", "Offset")


class SweepFeature(OperationFeature):
    """Editing Radius0, Radius1 or Offset moves the profile's inner control points in
    proportion (`retuned_profile`), as in the paper's parameter tuning, so the shape keeps
    its character instead of kinking."""

    TYPE = "Sketch2CAD::Sweep"
    OPERATION = Sweep
    LABEL = "Sweep"

    def add_operation_properties(self, obj) -> None:
        obj.addProperty("App::PropertyVector", "Center", GROUP, "Centre of c0 on face f (mm)")
        obj.addProperty("App::PropertyLength", "Radius0", GROUP, "r0: radius of c0 (mm)")
        obj.addProperty("App::PropertyLength", "Radius1", GROUP, "r1: radius of c1 (mm)")
        obj.addProperty("App::PropertyLength", "Offset", GROUP,
                        "d: distance from c0's centre to c1's along the axis (mm)")
        obj.addProperty("App::PropertyVectorList", "ProfileInner", GROUP,
                        "c_p: its two inner control points as (r, h, 0): distance from the "
                        "axis and height above c0 (mm)")
        obj.addProperty("App::PropertyEnumeration", "Mode", GROUP, MODE_TIP)
        obj.Mode = MODES

    def operation(self, obj) -> Sweep:
        if len(obj.ProfileInner) != 2:
            raise ValueError(f"{obj.Label}: ProfileInner needs 2 points, has "
                             f"{len(obj.ProfileInner)}")
        return Sweep(self.face(obj), tup(obj.Center), mm(obj.Radius0), mm(obj.Radius1),
                     mm(obj.Offset), tuple((p.x, p.y) for p in obj.ProfileInner), Mode(obj.Mode))

    def set_operation(self, obj, op: Sweep) -> None:
        self._tuning = True  # these values are a whole operation: nothing to retune
        try:
            super().set_operation(obj, op)
            obj.Center = vec(op.center)
            obj.Radius0, obj.Radius1, obj.Offset = op.r0, op.r1, op.d
            obj.ProfileInner = [FreeCAD.Vector(r, h, 0) for r, h in op.profile]
            obj.Mode = op.mode.value
        finally:
            self._tuning = False
        self._last = (op.r0, op.r1, op.d)

    def onChanged(self, obj, prop):
        if prop not in TUNED or getattr(self, "_tuning", False) \
                or not all(hasattr(obj, p) for p in TUNED + ("ProfileInner", "Mode")):
            return
        last = getattr(self, "_last", None)
        now = (mm(obj.Radius0), mm(obj.Radius1), mm(obj.Offset))
        self._last = now
        # Undo, redo and file loading set the profile themselves.
        if "Restore" in obj.State or obj.Document.Transacting or obj.Document.Restoring:
            return
        if last is None or min(last) <= 0 or min(now) <= 0 or len(obj.ProfileInner) != 2:
            return
        inner = tuple((p.x, p.y) for p in obj.ProfileInner)
        profile = retuned_profile(inner, last, now)
        self._tuning = True
        try:
            obj.ProfileInner = [FreeCAD.Vector(r, h, 0) for r, h in profile]
        finally:
            self._tuning = False

    def onDocumentRestored(self, obj):
        self._last = (mm(obj.Radius0), mm(obj.Radius1), mm(obj.Offset))
