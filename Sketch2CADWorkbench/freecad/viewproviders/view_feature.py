# SPDX-License-Identifier: LGPL-2.1-or-later
"""One view provider for all Sketch2CAD objects: the icon follows the object's type."""
import os

ICONS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                     "resources", "icons")
ICON_OF_TYPE = {"Sketch2CAD::Model": "Model", "Sketch2CAD::Box": "Box",
                "Sketch2CAD::Extrude": "Extrude", "Sketch2CAD::Bevel": "Bevel",
                "Sketch2CAD::AddSubPrism": "AddSubPrism", "Sketch2CAD::Sweep": "Sweep"}


def icon_path(name: str) -> str:
    return os.path.join(ICONS, f"{name}.svg")


class ViewProviderSketch2CAD:
    def __init__(self, vobj):
        vobj.Proxy = self
        self.type = vobj.Object.Proxy.TYPE

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon_path(ICON_OF_TYPE.get(getattr(self, "type", ""), "Sketch2CAD"))

    def __getstate__(self):
        return {"type": getattr(self, "type", "")}

    def __setstate__(self, state):
        if state:
            self.type = state.get("type", "")

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)
