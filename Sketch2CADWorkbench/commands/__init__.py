# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI commands (as Draft's draftguitools): each gathers input, calls a make_* function
or the core, and changes the document in one undo step; errors go to a message box."""

from .export import ExportStep
from .model import NewModel
from .partdesign import ConvertToPartDesign
from .protocol import LoadProtocol, ReplayProtocol, SaveProtocol
from .sketch import Sketch

COMMANDS = {
    "Sketch2CAD_NewModel": NewModel(),
    "Sketch2CAD_Sketch": Sketch(),
    "Sketch2CAD_LoadProtocol": LoadProtocol(),
    "Sketch2CAD_SaveProtocol": SaveProtocol(),
    "Sketch2CAD_ReplayProtocol": ReplayProtocol(),
    "Sketch2CAD_ExportStep": ExportStep(),
    "Sketch2CAD_ConvertToPartDesign": ConvertToPartDesign(),
}
TOOLBAR = [
    "Sketch2CAD_NewModel",
    "Sketch2CAD_Sketch",
    "Separator",
    "Sketch2CAD_LoadProtocol",
    "Sketch2CAD_SaveProtocol",
    "Sketch2CAD_ReplayProtocol",
    "Separator",
    "Sketch2CAD_ExportStep",
    "Sketch2CAD_ConvertToPartDesign",
]
MENU = TOOLBAR
