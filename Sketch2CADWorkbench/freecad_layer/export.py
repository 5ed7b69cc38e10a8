# SPDX-License-Identifier: LGPL-2.1-or-later
"""A model's final solid as a STEP file, written by FreeCAD's own STEP writer."""
import os
import tempfile
from pathlib import Path

import FreeCAD  # noqa: F401  (Import needs FreeCAD imported first)
import Import


def export_step(model, path) -> None:
    """Write the model's final solid (its Tip's shape) as STEP, in mm.

    FreeCAD's writer (`Import.export`) uses the scheme chosen in FreeCAD's STEP
    preferences, AP214 unless the user changed it, and names the product after the Tip.
    The file appears only once completely written, so a failure leaves any previous file
    at `path` as it was.

    Args:
        model: a Sketch2CAD model (see make_model).
        path: the .step or .stp file to write.

    Raises:
        ValueError: the model's last step is in error or has no solid.
        OSError: the file cannot be written.
    """
    tip, path = model.Tip, Path(path)
    if tip is None or not tip.isValid() or tip.Shape.isNull():
        name = tip.Label if tip is not None else "none"
        raise ValueError(f"{model.Label}: its last step ({name}) has no valid solid; fix it "
                         "before exporting")
    fd, tmp = tempfile.mkstemp(suffix=path.suffix or ".step", dir=path.parent)
    os.close(fd)
    try:
        Import.export([tip], tmp)
        if os.path.getsize(tmp) == 0:
            raise OSError(f"{path}: FreeCAD's STEP writer wrote nothing")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
