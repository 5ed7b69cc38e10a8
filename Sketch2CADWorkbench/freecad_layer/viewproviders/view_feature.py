# SPDX-License-Identifier: LGPL-2.1-or-later
"""One view provider for all Sketch2CAD objects: the tree icon follows the object's kind
(Pad or Pocket, Boss or Hole...), and double-clicking a sketched step opens its Sketch
panel with its strokes, as PartDesign reopens a Pad's panel."""

from ..icons import icon_path

ICON_OF_TYPE = {
    "Sketch2CAD::Model": "Model",
    "Sketch2CAD::Box": "Box",
    "Sketch2CAD::Extrude": "Pad",
    "Sketch2CAD::Bevel": "Bevel",
    "Sketch2CAD::AddSubPrism": "Boss",
    "Sketch2CAD::Sweep": "Revolution",
    "Sketch2CAD::Shell": "Thickness",
}
EDIT = 0  # FreeCAD's default edit mode; 1 (Transform) and the others are FreeCAD's own


class ViewProviderSketch2CAD:
    """Proxy of the view object; it saves the object's type so that the icon is known
    before the App proxy is restored."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.type = vobj.Object.Proxy.TYPE

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        obj = getattr(self, "Object", None)
        proxy = getattr(obj, "Proxy", None)
        if hasattr(proxy, "kind"):
            try:
                return icon_path(proxy.kind(obj))
            except (ValueError, AttributeError):
                pass  # being restored: its properties are not all there yet
        return icon_path(ICON_OF_TYPE.get(getattr(self, "type", ""), "Sketch2CAD"))

    def updateData(self, obj, prop):
        if prop in getattr(obj.Proxy, "KIND_PROPERTIES", ()):
            obj.ViewObject.signalChangeIcon()

    def _editable(self, vobj) -> bool:
        return hasattr(getattr(vobj.Object, "Proxy", None), "OPERATION")

    def doubleClicked(self, vobj):
        """A sketched step opens its Sketch panel; the model and the box do nothing (their
        Placement is not theirs to move, so no Transform dragger)."""
        import FreeCADGui

        if self._editable(vobj) and not FreeCADGui.Control.activeDialog():
            FreeCADGui.ActiveDocument.setEdit(vobj.Object, EDIT)
        return True

    def setupContextMenu(self, vobj, menu):
        if not self._editable(vobj):
            return
        from PySide import QtGui

        from ..translate import translate

        action = QtGui.QAction(
            QtGui.QIcon(icon_path("Sketch")), translate("Sketch2CAD", "Edit sketch step"), menu
        )
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)

    def setEdit(self, vobj, mode=0):
        if mode != EDIT or not self._editable(vobj):
            return None  # FreeCAD's own (Transform...)
        import FreeCADGui

        from ..gui_helpers import error
        from ..taskpanels.sketch_panel import SketchPanel
        from ..translate import translate

        view = FreeCADGui.ActiveDocument.ActiveView
        if view.getCameraType() != "Orthographic":  # as the Sketch command does
            view.setCameraType("Orthographic")
        try:
            panel = SketchPanel(_model_of(vobj.Object), vobj.Object)
        except ValueError as e:
            error(translate("Sketch2CAD", "Cannot edit the sketch step"), str(e))
            return False
        FreeCADGui.Control.showDialog(panel)
        self.panel = panel
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != EDIT:
            return None
        panel, self.panel = getattr(self, "panel", None), None
        if panel is not None:  # FreeCAD leaves the edit: the panel goes, changing nothing
            panel.close(reset_edit=False)
        return True

    # FreeCAD 0.20 pickles proxies through __getstate__/__setstate__; 0.21.2+ dumps/loads.
    def __getstate__(self):
        return {"type": getattr(self, "type", "")}

    def __setstate__(self, state):
        self.type = (state or {}).get("type", "")

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)


def _model_of(obj):
    """The model whose Group holds the feature."""
    return next(o for o in obj.InList if obj in getattr(o, "Group", []))
