# SPDX-License-Identifier: LGPL-2.1-or-later
"""The see-through preview of a reading over the 3D view."""

from pivy import coin

# Blue, see-through: unlike FreeCAD's green selection, yellow pre-selection and the
# strokes' orange.
COLOUR = (0.25, 0.45, 0.95)
TRANSPARENCY = 0.5


class Preview:
    """One shape shown over the view's scene until replaced or removed."""

    def __init__(self, view):
        self.graph = view.getSceneGraph()
        self.node = None

    def show(self, shape) -> None:
        """Show the Part shape (None: show nothing)."""
        self.remove()
        if shape is None:
            return
        node = coin.SoSeparator()
        mat = coin.SoMaterial()
        mat.diffuseColor = COLOUR
        mat.transparency = TRANSPARENCY
        node.addChild(mat)
        node.addChild(_mesh_node(shape))
        self.graph.addChild(node)
        self.node = node

    def remove(self) -> None:
        if self.node is not None:
            self.graph.removeChild(self.node)
            self.node = None


def _mesh_node(shape, tolerance: float = 0.1):
    """Coin nodes of the shape's triangles (built directly: the text of writeInventor()
    differs between FreeCAD versions, and FreeCAD 1.0's is not read back by Coin)."""
    points, triangles = shape.tessellate(tolerance)
    group = coin.SoGroup()
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, len(points), [(p.x, p.y, p.z) for p in points])
    faces = coin.SoIndexedFaceSet()
    faces.coordIndex.setValues(0, 4 * len(triangles), [i for tri in triangles for i in (*tri, -1)])
    group.addChild(coords)
    group.addChild(faces)
    return group
