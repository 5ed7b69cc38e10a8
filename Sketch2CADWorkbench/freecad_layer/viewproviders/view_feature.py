# SPDX-License-Identifier: LGPL-2.1-or-later
"""One view provider for all Sketch2CAD objects: the tree icon follows the object's type."""
from ..icons import icon_path

ICON_OF_TYPE = {"Sketch2CAD::Model": "Model", "Sketch2CAD::Box": "Box",
                "Sketch2CAD::Extrude": "Extrude", "Sketch2CAD::Bevel": "Bevel",
                "Sketch2CAD::AddSubPrism": "AddSubPrism", "Sketch2CAD::Sweep": "Sweep"}


class ViewProviderSketch2CAD:
    """Proxy of the view object; it saves the object's type so that the icon is known
    before the App proxy is restored."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.type = vobj.Object.Proxy.TYPE

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon_path(ICON_OF_TYPE.get(getattr(self, "type", ""), "Sketch2CAD"))

    # FreeCAD 0.20 pickles proxies through __getstate__/__setstate__; 0.21.2+ dumps/loads.
    def __getstate__(self):
        return {"type": getattr(self, "type", "")}

    def __setstate__(self, state):
        self.type = (state or {}).get("type", "")

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)
