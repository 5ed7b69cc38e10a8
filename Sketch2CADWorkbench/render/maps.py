# SPDX-License-Identifier: LGPL-2.1-or-later
"""Context maps of a solid seen by an orthographic camera, rendered offscreen with VTK.

One GPU pass draws each triangle in a flat colour that encodes its index (no lighting,
no anti-aliasing, so colours come back exactly). Everything else follows exactly from
the triangle under each pixel centre: its B-rep face, and, by barycentric interpolation
at the pixel centre, the depth of its plane (exact, no z-buffer quantisation) and the
face's smooth surface normal. The window and pipeline are made once per MapRenderer.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import cadquery as cq
import numpy as np
import vtkmodules.vtkRenderingOpenGL2 as _opengl  # registers the OpenGL implementations
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR, vtkPoints, vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow

from ..brep.faces import model_scale
from .camera import OrthoCamera
from .mesh import FaceMesh, tessellate, view_tolerance

MAX_TRIANGLES = (1 << 24) - 2  # triangle index + 1 must fit in 24 bits of RGB
# How far outside its triangle (in barycentric weight) a pixel centre is taken as is.
BARY_SLACK = 1e-3
# Pixels on triangles of smaller projected area (square pixels) are interpolated in
# float64: such slivers are seen nearly edge-on and have steep depth slopes.
THIN_AREA = 0.5


@dataclass
class ContextMaps:
    """The rendered context; (H, W) maps in the camera's pixel convention (render/camera.py).

    Camera space is the right-handed frame (right, up, -forward) of camera.basis():
    x to the right of the image, y up the image, z towards the viewer. Outward normals
    of surfaces facing the viewer therefore have z > 0, i.e. normal[2] > 1.

    Attributes:
        depth: D, float32: view depth mapped linearly so that the farthest visible
            foreground point is 0 and the closest is 1 (all 1 if the foreground has one
            depth); background 0 (paper, "Context Driven Sketch Interpretation").
        normal: N, (3, H, W) float32: camera-space outward unit normal + (1, 1, 1);
            background 0.
        face_id: int32 index into solid.Faces() of the face each pixel centre sees;
            -1 on background.
        view_depth: float32 depth in mm along camera.direction from the plane through
            camera.center, as camera.project measures it (larger is farther); +inf on
            background. None for maps read back from a stored sample, which keeps D only
            (what needs it, visibility and pictures, takes rendered maps).
    """

    depth: np.ndarray
    normal: np.ndarray
    face_id: np.ndarray
    view_depth: np.ndarray | None

    @property
    def foreground(self) -> np.ndarray:
        """(H, W) bool: pixels that see the solid."""
        return self.face_id >= 0


def offscreen_window() -> vtkRenderWindow:
    """An offscreen VTK render window.

    Without a display, the EGL window is made directly: the generic factory would try
    X first and print a warning before falling back to EGL.
    """
    if (
        os.name == "posix"
        and not os.environ.get("DISPLAY")
        and hasattr(_opengl, "vtkEGLRenderWindow")
    ):
        window = _opengl.vtkEGLRenderWindow()
    else:
        window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    return window


def polydata(mesh: FaceMesh) -> vtkPolyData:
    """A VTK triangle mesh of a FaceMesh: points and triangle cells, no attributes."""
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(mesh.vertices, dtype=np.float64), deep=True))
    pd.SetPoints(pts)
    n = len(mesh.triangles)
    cells = vtkCellArray()
    cells.SetData(
        numpy_to_vtkIdTypeArray(np.arange(0, 3 * n + 1, 3, dtype=np.int64), deep=True),
        numpy_to_vtkIdTypeArray(mesh.triangles.astype(np.int64).ravel(), deep=True),
    )
    pd.SetPolys(cells)
    return pd


def set_vtk_camera(vcam, camera: OrthoCamera, depth_range: tuple[float, float]) -> None:
    """Point a vtkCamera like `camera`, with its near and far planes around `depth_range`.

    Args:
        vcam: the vtkCamera to set.
        camera: the view.
        depth_range: (nearest, farthest) view depth (mm, as camera.project) of the scene;
            the eye is put in front of the nearest point.
    """
    lo, hi = depth_range
    margin = 1e-2 * max(hi - lo, camera.scale)
    dist = max(-lo, 0.0) + 2.0 * margin  # eye distance to camera.center
    c = np.asarray(camera.center, float)
    _, up, fwd = camera.basis()
    vcam.SetParallelProjection(True)
    vcam.SetFocalPoint(*c)
    vcam.SetPosition(*(c - fwd * dist))
    vcam.SetViewUp(*up)
    vcam.SetParallelScale(camera.scale)
    vcam.SetClippingRange(dist + lo - margin, dist + hi + margin)


class MapRenderer:
    """A reusable offscreen VTK pipeline that renders ContextMaps.

    Not thread-safe; make one per process (or thread). The last mesh's VTK copy is kept,
    so rendering the same FaceMesh from several cameras uploads it once.
    """

    def __init__(self):
        self.window = offscreen_window()
        self.window.SetMultiSamples(0)  # exact colours: IDs must not blend at edges
        # Pixels are read from the offscreen framebuffer; copying each frame on to the
        # window's own buffers would take most of the render time.
        self.window.SwapBuffersOff()
        self.renderer = vtkRenderer()
        self.renderer.SetBackground(0.0, 0.0, 0.0)  # colour 0 = no triangle
        self.renderer.AutomaticLightCreationOff()
        self.window.AddRenderer(self.renderer)
        self.mapper = vtkPolyDataMapper()
        self.mapper.SetColorModeToDirectScalars()
        self.mapper.SetScalarModeToUseCellData()
        actor = vtkActor()
        actor.SetMapper(self.mapper)
        prop = actor.GetProperty()
        prop.LightingOff()  # colours are data, not shading
        prop.SetInterpolationToFlat()
        self.renderer.AddActor(actor)
        self._mesh: FaceMesh | None = None
        self._buffer = vtkUnsignedCharArray()

    def close(self) -> None:
        """Release the window's graphics context (the renderer is unusable afterwards)."""
        self.window.Finalize()

    def render(self, shape: cq.Shape | FaceMesh, camera: OrthoCamera) -> ContextMaps:
        """Depth, normal, face-ID and view-depth maps of a solid seen by `camera`.

        Args:
            shape: a solid, tessellated here to mesh.view_tolerance for `camera`, or a mesh.
            camera: the view; the maps are camera.height x camera.width.
        Returns:
            The maps.
        Raises:
            ValueError: the mesh has more triangles than the colour encoding holds.
        """
        if isinstance(shape, FaceMesh):
            mesh = shape
        else:
            mesh = tessellate(shape, view_tolerance(model_scale(shape), camera.pixel_size))
        pixels, depths = camera.project(mesh.vertices)
        triangle = self.triangle_ids(mesh, camera, (float(depths.min()), float(depths.max())))
        return _surface_maps(mesh, camera, triangle, pixels, depths)

    def triangle_ids(
        self, mesh: FaceMesh, camera: OrthoCamera, depth_range: tuple[float, float]
    ) -> np.ndarray:
        """(H, W) int32 index of the triangle seen at each pixel centre, -1 on background.

        Args:
            mesh: the mesh.
            camera: the view.
            depth_range: (nearest, farthest) view depth (mm) of the mesh's vertices.
        """
        if len(mesh.triangles) > MAX_TRIANGLES:
            raise ValueError(
                f"{len(mesh.triangles)} triangles exceed the {MAX_TRIANGLES} "
                "that the colour encoding holds"
            )
        if mesh is not self._mesh:
            pd = polydata(mesh)
            code = np.arange(1, len(mesh.triangles) + 1, dtype=np.int64)
            rgb = np.stack([code & 255, (code >> 8) & 255, (code >> 16) & 255], axis=1)
            colours = numpy_to_vtk(
                np.ascontiguousarray(rgb, dtype=np.uint8), deep=True, array_type=VTK_UNSIGNED_CHAR
            )
            pd.GetCellData().SetScalars(colours)
            self.mapper.SetInputData(pd)
            self._mesh = mesh
        w, h = camera.width, camera.height
        if tuple(self.window.GetSize()) != (w, h):
            self.window.SetSize(w, h)
        set_vtk_camera(self.renderer.GetActiveCamera(), camera, depth_range)
        self.window.Render()
        self.window.GetRGBACharPixelData(0, 0, w - 1, h - 1, 0, self._buffer)
        # Bytes R, G, B, A as one little-endian word: R | G << 8 | B << 16 | A << 24.
        rgba = vtk_to_numpy(self._buffer).view("<u4").reshape(h, w)[::-1]
        return (rgba & 0xFFFFFF).astype(np.int32) - 1


def _surface_maps(
    mesh: FaceMesh,
    camera: OrthoCamera,
    triangle: np.ndarray,
    pixels: np.ndarray,
    depths: np.ndarray,
) -> ContextMaps:
    """The maps from the triangle seen at each pixel, by interpolation at pixel centres.

    Args:
        mesh: the mesh.
        camera: the view.
        triangle: (H, W) triangle index per pixel, -1 on background.
        pixels, depths: the vertices projected by camera.project.
    """
    h, w = triangle.shape
    r, u, f = camera.basis()
    # Per vertex: view depth and camera-space normal (x right, y up, z to the viewer).
    attrs = np.concatenate([depths[:, None], mesh.vertex_normals @ np.stack([r, u, -f]).T], axis=1)
    # Pixel positions are taken from the image centre, which keeps the affine
    # coefficients small enough for float32; float32 halves the per-pixel work.
    centre = np.array([w / 2.0, h / 2.0])
    coef, thin = _affine_coefficients(mesh.triangles, pixels - centre, attrs)

    flat = triangle.ravel()
    index = np.flatnonzero(flat >= 0)
    seen = flat[index]
    x = index % w + (0.5 - centre[0])
    y = index // w + (0.5 - centre[1])
    # One attribute per row, one pixel per column: every step below runs over
    # contiguous rows (np.take: faster than fancy indexing).
    cx, cy, c0 = np.ascontiguousarray(coef.astype(np.float32).transpose(2, 1, 0))
    values = np.take(cx, seen, axis=1)
    values *= x.astype(np.float32)
    values += np.take(cy, seen, axis=1) * y.astype(np.float32)
    values += np.take(c0, seen, axis=1)
    l1, l2 = values[4], values[5]
    # The rasteriser may take a centre a hair outside its triangle, and on slivers seen
    # edge-on the coefficients are too large for float32: redo those pixels in float64
    # at the point of the triangle nearest in barycentric weights.
    redo = np.flatnonzero(
        (l1 < -BARY_SLACK) | (l2 < -BARY_SLACK) | (l1 + l2 > 1 + BARY_SLACK) | np.take(thin, seen)
    )
    if len(redo):
        t = seen[redo]
        xy1 = np.stack([x[redo], y[redo], np.ones(len(redo))], axis=1)
        b1, b2 = (np.einsum("qk,qk->q", coef[t, row], xy1) for row in (-2, -1))
        lam = np.clip(np.stack([1.0 - b1 - b2, b1, b2], axis=1), 0.0, 1.0)
        lam /= lam.sum(axis=1, keepdims=True)
        values[:4, redo] = np.einsum("qk,qka->aq", lam, attrs[mesh.triangles[t]])

    view_depth = np.full(h * w, np.inf, np.float32)
    view_depth[index] = values[0]
    n = values[1:4]
    n /= np.maximum(np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1e-12)
    n += 1.0
    normal = np.zeros((3, h * w), np.float32)
    for channel, row in zip(normal, n, strict=False):
        channel[index] = row
    face_id = np.full(h * w, -1, np.int32)
    face_id[index] = np.take(mesh.face_index, seen)
    view_depth = view_depth.reshape(h, w)
    return ContextMaps(
        normalized_depth(view_depth), normal.reshape(3, h, w), face_id.reshape(h, w), view_depth
    )


def _affine_coefficients(
    triangles: np.ndarray, pixels: np.ndarray, attrs: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per triangle, the affine functions of the pixel position (x, y) that interpolate
    the vertex attributes linearly across the projected triangle.

    Args:
        triangles: (T, 3) vertex indices.
        pixels: (V, 2) projected vertex positions (pixels).
        attrs: (V, A) vertex attributes.
    Returns:
        coef: (T, A + 2, 3) float64: for each triangle, rows (cx, cy, c0) such that
            value = cx x + cy y + c0; rows A and A + 1 are the barycentric weights of
            vertices 1 and 2. Triangles of no projected area get their centroid's values.
        thin: (T,) bool: triangles of under THIN_AREA square pixels.
    """
    a, b, c = (pixels[triangles[:, k]] for k in range(3))
    e1, e2 = b - a, c - a
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]  # twice the signed projected area
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    l1 = np.stack(
        [e2[:, 1] * inv, -e2[:, 0] * inv, (a[:, 1] * e2[:, 0] - a[:, 0] * e2[:, 1]) * inv], axis=1
    )
    l2 = np.stack(
        [-e1[:, 1] * inv, e1[:, 0] * inv, (a[:, 0] * e1[:, 1] - a[:, 1] * e1[:, 0]) * inv], axis=1
    )
    l1[~ok, 2] = l2[~ok, 2] = 1.0 / 3.0
    v0, v1, v2 = (attrs[triangles[:, k]] for k in range(3))
    coef = (v1 - v0)[:, :, None] * l1[:, None, :] + (v2 - v0)[:, :, None] * l2[:, None, :]
    coef[:, :, 2] += v0
    return (
        np.concatenate([coef, l1[:, None, :], l2[:, None, :]], axis=1),
        np.abs(det) < 2.0 * THIN_AREA,
    )


def normalized_depth(view_depth: np.ndarray) -> np.ndarray:
    """The paper's D from view depths: farthest foreground 0, closest 1, background 0.

    Args:
        view_depth: (H, W) depth in mm, +inf on background.
    Returns:
        (H, W) float32.
    """
    fg = np.isfinite(view_depth)
    out = np.zeros(view_depth.shape, np.float32)
    if fg.any():
        vals = view_depth[fg]
        lo, hi = float(vals.min()), float(vals.max())
        out[fg] = 1.0 if hi - lo <= 1e-9 * max(abs(lo), abs(hi), 1.0) else (hi - vals) / (hi - lo)
    return out
