# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared renderer and shapes for the render tests (one offscreen window for them all)."""

import cadquery as cq
import numpy as np
import pytest

from Sketch2CADWorkbench.brep.operators import make_box
from Sketch2CADWorkbench.brep.protocol import Box
from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.render.maps import MapRenderer

BOX_SIZE = (40.0, 30.0, 20.0)


@pytest.fixture(scope="session")
def renderer():
    r = MapRenderer()
    yield r
    r.close()


@pytest.fixture(scope="session")
def box_size():
    """(lx, ly, lz) of the test box, mm."""
    return np.array(BOX_SIZE)


@pytest.fixture(scope="session")
def box():
    """The box of BOX_SIZE centred on the origin."""
    return make_box(Box(BOX_SIZE))


@pytest.fixture(scope="session")
def cylinder():
    """Radius 10, height 20, axis +z from the origin."""
    return cq.Solid.makeCylinder(10.0, 20.0)


@pytest.fixture(scope="session")
def oblique():
    """A 256 x 256 view from +x, -y and above: the box's +x, -y and top faces show."""
    d = np.array([-0.7, 1.0, -1.1])
    return OrthoCamera((0.0, 0.0, 0.0), tuple(d / np.linalg.norm(d)), (0, 0, 1), 35.0)


@pytest.fixture(scope="session")
def face_of():
    """face_of(solid, normal): index in solid.Faces() of the planar face with that normal."""

    def find(solid, normal) -> int:
        return next(
            i
            for i, f in enumerate(solid.Faces())
            if f.geomType() == "PLANE" and np.dot(f.normalAt().toTuple(), normal) > 0.999
        )

    return find
