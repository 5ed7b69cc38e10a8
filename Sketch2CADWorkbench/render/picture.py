# SPDX-License-Identifier: LGPL-2.1-or-later
"""Pictures a person looks at: shaded solids with their B-rep edges, strokes, contact sheets."""
from __future__ import annotations

from pathlib import Path

import cadquery as cq
import cv2
import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from .camera import OrthoCamera
from .frustum import fit_camera
from .maps import polydata, set_vtk_camera
from .mesh import tessellate

DEFAULT_DIRECTION = (-1.0, 1.0, -0.8)  # from front-right, above: three faces of a box show
BODY = (0.72, 0.78, 0.86)
STROKE_BGR = (0, 140, 255)  # orange


def default_camera(solid: cq.Shape, width: int = 800, height: int = 600) -> OrthoCamera:
    bb = solid.BoundingBox()
    return fit_camera((bb.xmin, bb.ymin, bb.zmin), (bb.xmax, bb.ymax, bb.zmax),
                      DEFAULT_DIRECTION, (0, 0, 1), 1.15, width, height)


def _edge_lines(solid: cq.Shape, spacing: float) -> vtk.vtkPolyData:
    """The solid's B-rep edges as VTK polylines (the CAD edges, not mesh edges)."""
    pts, lines = vtk.vtkPoints(), vtk.vtkCellArray()
    for e in solid.Edges():
        n = 2 if e.geomType() == "LINE" else max(int(e.Length() / spacing), 8)
        ids = []
        for t in np.linspace(0, 1, n):
            ids.append(pts.InsertNextPoint(*e.positionAt(t).toTuple()))
        line = vtk.vtkPolyLine()
        line.GetPointIds().SetNumberOfIds(len(ids))
        for k, i in enumerate(ids):
            line.GetPointIds().SetId(k, i)
        lines.InsertNextCell(line)
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(lines)
    return pd


def shaded_picture(solid: cq.Shape, camera: OrthoCamera | None = None,
                   size: tuple[int, int] = (800, 600), path: str | Path | None = None,
                   strokes: list[np.ndarray] | None = None) -> np.ndarray:
    """A shaded picture of the solid with black B-rep edges on white.

    Args:
        solid: the shape.
        camera: the view (its width/height win over `size`); by default a view from
            front-right above that frames the solid.
        size: (width, height) of the default view.
        path: write the picture as PNG there (only once it is complete).
        strokes: pixel polylines in the camera's pixels, drawn over it in orange.
    Returns:
        (H, W, 3) uint8 RGB.
    """
    cam = camera or default_camera(solid, *size)
    w, h = cam.width, cam.height
    mesh = tessellate(solid, 1e-3 * solid.BoundingBox().DiagonalLength, 0.1)
    pd = polydata(mesh)
    nrm = numpy_to_vtk(np.ascontiguousarray(mesh.normals), deep=True)
    pd.GetPointData().SetNormals(nrm)

    ren = vtk.vtkRenderer()
    ren.SetBackground(1, 1, 1)
    body = vtk.vtkActor()
    m = vtk.vtkPolyDataMapper()
    m.SetInputData(pd)
    m.SetResolveCoincidentTopologyToPolygonOffset()  # edges drawn over their faces
    body.SetMapper(m)
    p = body.GetProperty()
    p.SetColor(*BODY)
    p.SetAmbient(0.25)
    p.SetDiffuse(0.7)
    p.SetSpecular(0.15)
    p.SetSpecularPower(20)
    ren.AddActor(body)
    edges = vtk.vtkActor()
    em = vtk.vtkPolyDataMapper()
    em.SetInputData(_edge_lines(solid, solid.BoundingBox().DiagonalLength / 200))
    edges.SetMapper(em)
    edges.GetProperty().SetColor(0.05, 0.05, 0.08)
    edges.GetProperty().SetLineWidth(max(1.5, w / 500))
    ren.AddActor(edges)
    depths = (mesh.vertices - np.asarray(cam.center)) @ cam.basis()[2]
    set_vtk_camera(ren.GetActiveCamera(), cam, (float(depths.min()), float(depths.max())))
    light = vtk.vtkLight()
    light.SetLightTypeToCameraLight()
    light.SetPosition(-0.4, 0.6, 1.0)
    ren.AddLight(light)

    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(True)
    win.SetMultiSamples(8)
    win.SetSize(w, h)
    win.AddRenderer(ren)
    win.Render()
    buf = vtk.vtkUnsignedCharArray()
    win.GetPixelData(0, 0, w - 1, h - 1, 1, buf, 0)
    rgb = np.ascontiguousarray(vtk_to_numpy(buf).reshape(h, w, 3)[::-1])
    win.Finalize()
    if strokes:
        bgr = rgb[..., ::-1].copy()
        for s in strokes:
            pts = np.round((np.asarray(s, float) - 0.5) * 16).astype(np.int32).reshape(-1, 1, 2)
            cv2.polylines(bgr, [pts], False, STROKE_BGR, max(2, w // 300), cv2.LINE_AA, 4)
        rgb = bgr[..., ::-1].copy()
    if path is not None:
        write_png(rgb, path)
    return rgb


def write_png(rgb: np.ndarray, path: str | Path) -> None:
    """Write an RGB picture; the file appears only once it is complete."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp.png")
    if not cv2.imwrite(str(tmp), rgb[..., ::-1]):
        raise OSError(f"{path}: cannot write the picture")
    tmp.replace(path)


def contact_sheet(images: list[np.ndarray], cols: int, labels: list[str] | None = None,
                  pad: int = 6) -> np.ndarray:
    """Images (H, W, 3) uint8, all the same size, on a white grid, with optional captions."""
    h, w = images[0].shape[:2]
    rows = (len(images) + cols - 1) // cols
    cap = 22 if labels else 0
    sheet = np.full((rows * (h + pad + cap) + pad, cols * (w + pad) + pad, 3), 255, np.uint8)
    for k, img in enumerate(images):
        r, c = divmod(k, cols)
        y, x = pad + r * (h + pad + cap), pad + c * (w + pad)
        sheet[y:y + h, x:x + w] = img
        if labels:
            cv2.putText(sheet, labels[k], (x + 2, y + h + 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45,
                        (20, 20, 20), 1, cv2.LINE_AA)
    return sheet
