# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writing and reading solids: STEP (AP214, mm) for users, BREP text for FreeCAD."""

from __future__ import annotations

import io
from pathlib import Path

import cadquery as cq
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

from .faces import OperationError
from .files import write_atomically


def export_step(solid: cq.Shape, path: str | Path) -> None:
    """Write `solid` as a STEP AP214 file in millimetres.

    The file appears only once it is completely written, so a failure leaves any
    previous file at `path` as it was (brep/files.py, which also says how links and
    devices are written).

    Raises:
        OSError: the file cannot be written (naming `path`; a full disk said so).
        OperationError: OCCT cannot express the solid as STEP.
    """
    write_atomically(path, step_bytes(solid))


def step_bytes(solid: cq.Shape) -> bytes:
    """The STEP AP214 text of `solid`, in millimetres, as cadquery's `exportStep`
    writes it; made in memory, so that writing it to disk fails only as a file write
    does (a full disk is reported as one, not as OCCT's bare failure).

    Raises:
        OperationError: OCCT cannot express the solid as STEP.
    """
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    Interface_Static.SetIVal_s("write.surfacecurve.mode", 1)
    Interface_Static.SetIVal_s("write.precision.mode", 0)
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    writer = STEPControl_Writer()
    buf = io.BytesIO()
    if (
        writer.Transfer(solid.wrapped, STEPControl_AsIs) != IFSelect_RetDone
        or writer.WriteStream(buf) != IFSelect_RetDone
    ):
        raise OperationError("OCCT could not express the solid as STEP")
    return buf.getvalue()


def import_step(path: str | Path) -> cq.Shape:
    """Read a STEP file into one shape (a compound when it holds several solids).

    Raises:
        OperationError: the file is missing or not readable STEP.
    """
    path = Path(path)
    if not path.is_file():
        raise OperationError(f"{path}: no such STEP file")
    try:
        return cq.importers.importStep(str(path)).val()
    except Exception as e:  # cadquery raises ValueError or OCCT errors on bad files
        raise OperationError(f"{path}: cannot read STEP: {e}") from None


def to_brep_text(shape: cq.Shape) -> str:
    """The shape as OCCT BREP text, the form in which shapes cross to FreeCAD's OCCT."""
    buf = io.BytesIO()
    shape.exportBrep(buf)
    return buf.getvalue().decode()


def from_brep_text(text: str) -> cq.Shape:
    """A shape from OCCT BREP text (as written by FreeCAD's `exportBrepToString`)."""
    return cq.Shape.importBrep(io.BytesIO(text.encode()))
