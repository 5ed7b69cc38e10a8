# SPDX-License-Identifier: LGPL-2.1-or-later
"""A model's final solid as a STEP file, written by FreeCAD's own STEP writer."""

from pathlib import Path

import FreeCAD  # Import needs FreeCAD imported first
import Import

from ..brep.files import atomic_path
from .queries import refuse_failed_steps


def export_step(model, path) -> None:
    """Write the model's final solid (its Tip's shape) as STEP, in mm.

    FreeCAD's writer (`Import.export`) uses the scheme chosen in FreeCAD's STEP
    preferences, AP214 unless the user changed it. The part is named after the model
    (the product's name is the exported object's label: a copy of the Tip's solid,
    labelled as the model, in a hidden scratch document).
    The file appears only once completely written, so a failure leaves any previous file
    at `path` as it was.

    Args:
        model: a Sketch2CAD model (see make_model).
        path: the .step or .stp file to write.

    Raises:
        ValueError: a step of the model is in error (named), or the last has no solid.
        OSError: the file cannot be written.
    """
    tip, path = model.Tip, Path(path)
    refuse_failed_steps(model, "exporting")
    if tip is None or not tip.isValid() or tip.Shape.isNull():
        name = tip.Label if tip is not None else "none"
        raise ValueError(
            f"{model.Label}: its last step ({name}) has no valid solid; fix it before exporting"
        )
    active = FreeCAD.ActiveDocument
    scratch = FreeCAD.newDocument("Sketch2CADExport", hidden=True)
    try:
        part = scratch.addObject("Part::Feature", "Model")
        part.Label = model.Label
        part.Shape = tip.Shape
        with atomic_path(path) as tmp:
            Import.export([part], str(tmp))
            if not tmp.exists() or tmp.stat().st_size == 0:
                raise OSError(f"{path}: FreeCAD's STEP writer wrote nothing")
    finally:
        FreeCAD.closeDocument(scratch.Name)
        if active is not None:
            FreeCAD.setActiveDocument(active.Name)
