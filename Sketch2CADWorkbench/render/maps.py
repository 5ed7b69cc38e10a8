# SPDX-License-Identifier: LGPL-2.1-or-later
"""Context maps of a solid seen by an orthographic camera, rendered offscreen with VTK.

Two flat-coloured passes share one offscreen window: face IDs encoded as 24-bit colours
(per triangle, no lighting), then camera-space normals encoded as colours (per vertex,
interpolated, so curved faces shade smoothly). The z-buffer of the first pass gives
the depth. The window is made once per MapRenderer and reused for every render.
"""
from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy

from .camera import OrthoCamera
from .mesh import FaceMesh, tessellate

vtk.vtkObject.GlobalWarningDisplayOff()  # offscreen context probing is chatty and harmless


@dataclass
class ContextMaps:
    """The rendered context, all (H, W) in the camera's pixel convention.

    Attributes:
        depth: D, float32: the farthest visible foreground point 0, the closest 1,
            background 0 (paper, Sec. 4).
        normal: N, (3, H, W) float32: camera-space outward normal + (1, 1, 1), background
            0. Camera space: x = right, y = up, z = towards the viewer, so a face turned
            to the camera has N_z > 1.
        face_id: int32 index into solid.Faces() of the face each pixel sees, -1 background.
        view_depth: float32 depth in mm along the view direction, measured from the plane
            through camera.center (as camera.project's depth); +inf on background.
    """

    depth: np.ndarray
    normal: np.ndarray
    face_id: np.ndarray
    view_depth: np.ndarray


def polydata(mesh: FaceMesh) -> vtk.vtkPolyData:
    """A VTK triangle mesh of a FaceMesh (points and triangle cells only)."""
    pd = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(mesh.vertices, dtype=np.float64), deep=True))
    pd.SetPoints(pts)
    n = len(mesh.triangles)
    cells = vtk.vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 3 * n + 1, 3, dtype=np.int64), deep=True),
                  numpy_to_vtkIdTypeArray(mesh.triangles.astype(np.int64).ravel(), deep=True))
    pd.SetPolys(cells)
    return pd


def _rgb_array(values: np.ndarray) -> vtk.vtkUnsignedCharArray:
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.uint8), deep=True,
                       array_type=vtk.VTK_UNSIGNED_CHAR)
    arr.SetNumberOfComponents(3)
    return arr


def set_vtk_camera(vcam: vtk.vtkCamera, camera: OrthoCamera, depth_range: tuple[float, float]
                   ) -> float:
    """Point a VTK camera like `camera`; returns the eye's distance to camera.center.

    The clipping range is set to `depth_range` (view depths, mm) plus a margin, so the
    z-buffer spans exactly the scene.
    """
    lo, hi = depth_range
    margin = 1e-3 * max(hi - lo, 1.0) + 1e-3
    dist = max(-lo, 0.0) + 10.0 * margin + 1.0  # eye in front of everything
    c = np.asarray(camera.center, float)
    _, up, fwd = camera.basis()
    vcam.SetParallelProjection(True)
    vcam.SetFocalPoint(*c)
    vcam.SetPosition(*(c - fwd * dist))
    vcam.SetViewUp(*up)
    vcam.SetParallelScale(camera.scale)
    vcam.SetClippingRange(dist + lo - margin, dist + hi + margin)
    return dist


class MapRenderer:
    """A reusable offscreen VTK pipeline for context maps."""

    def __init__(self):
        self.window = vtk.vtkRenderWindow()
        self.window.SetOffScreenRendering(True)
        self.window.SetMultiSamples(0)  # exact colours: IDs must not blend at edges
        self.renderer = vtk.vtkRenderer()
        self.renderer.SetBackground(0, 0, 0)
        self.window.AddRenderer(self.renderer)
        self.mapper = vtk.vtkPolyDataMapper()
        self.mapper.SetColorModeToDirectScalars()
        self.actor = vtk.vtkActor()
        self.actor.SetMapper(self.mapper)
        prop = self.actor.GetProperty()
        prop.LightingOff()  # colours are data, not shading
        prop.SetInterpolationToFlat()
        self.renderer.AddActor(self.actor)

    def render(self, shape: cq.Shape | FaceMesh, camera: OrthoCamera) -> ContextMaps:
        """Depth, normal and face-ID maps of a solid (or its mesh) seen by `camera`."""
        mesh = shape if isinstance(shape, FaceMesh) else tessellate(shape)
        w, h = camera.width, camera.height
        self.window.SetSize(w, h)
        pd = polydata(mesh)
        right, up, fwd = camera.basis()
        depths = (mesh.vertices - np.asarray(camera.center)) @ fwd
        dist = set_vtk_camera(self.renderer.GetActiveCamera(), camera,
                              (float(depths.min()), float(depths.max())))
        near, far = self.renderer.GetActiveCamera().GetClippingRange()

        # Pass 1: face IDs (+1, so 0 is background) as 24-bit colours per triangle.
        ids = mesh.face_index.astype(np.int64) + 1
        pd.GetCellData().SetScalars(_rgb_array(
            np.stack([ids & 255, (ids >> 8) & 255, (ids >> 16) & 255], axis=1)))
        self.mapper.SetInputData(pd)
        self.mapper.SetScalarModeToUseCellData()
        rgb, z = self._draw(w, h, depth=True)
        face_id = (rgb[..., 0].astype(np.int32) | (rgb[..., 1].astype(np.int32) << 8)
                   | (rgb[..., 2].astype(np.int32) << 16)) - 1

        # Pass 2: camera-space normals (x right, y up, z to the viewer) per vertex.
        nc = np.stack([mesh.normals @ right, mesh.normals @ up, -(mesh.normals @ fwd)], axis=1)
        pd.GetCellData().SetScalars(None)
        pd.GetPointData().SetScalars(_rgb_array(np.round((nc + 1.0) * 127.5)))
        self.mapper.SetScalarModeToUsePointData()
        self.actor.GetProperty().SetInterpolationToGouraud()
        rgb2, _ = self._draw(w, h, depth=False)
        self.actor.GetProperty().SetInterpolationToFlat()

        fg = face_id >= 0
        view_depth = np.where(fg, near + z * (far - near) - dist, np.inf).astype(np.float32)
        normal = np.where(fg[None], rgb2.transpose(2, 0, 1) / 127.5, 0.0).astype(np.float32)
        return ContextMaps(normalized_depth(view_depth), normal, face_id, view_depth)

    def _draw(self, w: int, h: int, depth: bool) -> tuple[np.ndarray, np.ndarray | None]:
        """Render and read back RGB (H, W, 3) uint8 and the z-buffer, top row first."""
        self.window.Render()
        buf = vtk.vtkUnsignedCharArray()
        self.window.GetPixelData(0, 0, w - 1, h - 1, 0, buf, 0)
        rgb = vtk_to_numpy(buf).reshape(h, w, 3)[::-1]
        z = None
        if depth:
            zb = vtk.vtkFloatArray()
            self.window.GetZbufferData(0, 0, w - 1, h - 1, zb)
            z = vtk_to_numpy(zb).reshape(h, w)[::-1].astype(np.float64)
        return rgb, z


def normalized_depth(view_depth: np.ndarray) -> np.ndarray:
    """The paper's D: foreground depths mapped linearly, farthest 0, closest 1."""
    fg = np.isfinite(view_depth)
    out = np.zeros(view_depth.shape, np.float32)
    if fg.any():
        lo, hi = view_depth[fg].min(), view_depth[fg].max()
        out[fg] = 1.0 if hi - lo < 1e-12 else (hi - view_depth[fg]) / (hi - lo)
    return out
