# SPDX-License-Identifier: LGPL-2.1-or-later
"""Pictures a person looks at: shaded solids with their B-rep edges, strokes, contact sheets.

A picture is shaded from the same maps the networks see, rendered at twice the size
and averaged down (anti-aliasing): soft two-light shading of the camera-space normals,
and black lines where the visible B-rep face changes (edges and outlines) or the depth
jumps within a face (a curved face hiding part of itself).
"""

from __future__ import annotations

from pathlib import Path

import cadquery as cq
import cv2
import numpy as np

from ..brep.faces import model_scale
from ..brep.files import write_atomically
from .camera import OrthoCamera
from .frustum import fit_camera
from .maps import ContextMaps, MapRenderer
from .mesh import FaceMesh, tessellate, view_tolerance

EYE_SIDE = (1.0, -1.0, 0.8)  # default view: from front-right, above (three box faces show)
SUPERSAMPLE = 2
BODY_RGB = np.array([0.72, 0.78, 0.86])  # light grey-blue
EDGE_RGB = np.array([0.06, 0.06, 0.08])
STROKE_RGB = (255, 140, 0)  # orange
# Lights in camera space (x right, y up, z to the viewer): a key light from the upper
# left and a weaker fill from the lower right, so no visible face goes black.
KEY_LIGHT = np.array([-0.35, 0.55, 0.76])
FILL_LIGHT = np.array([0.55, -0.3, 0.78])
AMBIENT, KEY, FILL, SPECULAR = 0.32, 0.58, 0.22, 0.12
SHININESS_LOG2 = 4  # specular exponent 16
# Depth jumps within one face wider than this many pixels (second difference) are outlines.
CREASE_PX = 3.0


def default_camera(shape: cq.Shape | FaceMesh, width: int = 800, height: int = 600) -> OrthoCamera:
    """The default picture view: from EYE_SIDE, world z up, framing the shape.

    Args:
        shape: a solid (framed by its bounding box) or its mesh (framed tightly).
        width, height: picture size in pixels.
    """
    return fit_camera(shape, tuple(-np.asarray(EYE_SIDE)), (0.0, 0.0, 1.0), 1.1, (width, height))


def shaded_picture(
    solid: cq.Shape,
    camera: OrthoCamera | None = None,
    size: tuple[int, int] = (800, 600),
    path: str | Path | None = None,
    strokes: list[np.ndarray] | None = None,
    renderer: MapRenderer | None = None,
) -> np.ndarray:
    """A shaded picture of the solid with black B-rep edges on white.

    Args:
        solid: the shape.
        camera: the view (its width and height win over `size`); by default one from
            EYE_SIDE, world z up, that frames the solid.
        size: (width, height) in pixels of the default view.
        path: also write the picture there as PNG (the file appears only when complete).
        strokes: polylines in the camera's pixels, drawn over the picture in orange.
        renderer: a MapRenderer to reuse (one is made and released otherwise).
    Returns:
        (H, W, 3) uint8 RGB.
    """
    scale = model_scale(solid)
    if camera is None:
        # Frame the mesh rather than the B-rep box, which is loose on curved faces; the
        # model's diagonal spans about the picture's larger side.
        mesh = tessellate(solid, view_tolerance(scale, scale / (SUPERSAMPLE * max(size))))
        camera = default_camera(mesh, *size)
    else:
        mesh = tessellate(solid, view_tolerance(scale, camera.pixel_size / SUPERSAMPLE))
    w, h = camera.width, camera.height
    own = renderer is None
    renderer = renderer or MapRenderer()
    try:
        maps = renderer.render(mesh, camera.with_size(w * SUPERSAMPLE, h * SUPERSAMPLE))
    finally:
        if own:
            renderer.close()
    rgb = shade(maps, camera.pixel_size / SUPERSAMPLE)
    rgb = cv2.resize(rgb, (w, h), interpolation=cv2.INTER_AREA)
    picture = np.clip(np.round(rgb * 255), 0, 255).astype(np.uint8)
    if strokes:
        draw_strokes(picture, strokes)
    if path is not None:
        write_png(picture, path)
    return picture


def shade(maps: ContextMaps, pixel_size: float) -> np.ndarray:
    """(H, W, 3) float32 RGB in [0, 1]: the shaded, outlined solid on white.

    Args:
        maps: the rendered maps.
        pixel_size: the maps' pixel size (mm), to tell depth jumps from slopes.
    """
    fg = maps.foreground
    n = (maps.normal[:, fg] - 1.0).T  # (P, 3) camera-space unit normals of the solid
    key, fill = KEY_LIGHT / np.linalg.norm(KEY_LIGHT), FILL_LIGHT / np.linalg.norm(FILL_LIGHT)
    half = key + np.array([0.0, 0.0, 1.0])
    half = (half / np.linalg.norm(half)).astype(np.float32)
    light = (
        AMBIENT
        + KEY * np.clip(n @ key.astype(np.float32), 0, None)
        + FILL * np.clip(n @ fill.astype(np.float32), 0, None)
    )
    glint = np.clip(n @ half, 0, None)
    for _ in range(SHININESS_LOG2):  # repeated squaring: far faster than a float power
        glint *= glint
    rgb = np.ones(fg.shape + (3,), np.float32)
    rgb[fg] = light[:, None] * BODY_RGB.astype(np.float32) + SPECULAR * glint[:, None]
    rgb[outlines(maps, pixel_size)] = EDGE_RGB
    return np.clip(rgb, 0.0, 1.0, out=rgb)


def outlines(maps: ContextMaps, pixel_size: float) -> np.ndarray:
    """(H, W) bool: pixels on either side of a visible B-rep edge, outline or depth jump.

    Args:
        maps: the rendered maps.
        pixel_size: the maps' pixel size (mm).
    """
    fid = maps.face_id
    line = np.zeros(fid.shape, bool)
    for axis in (0, 1):
        a = [slice(None)] * 2
        b = [slice(None)] * 2
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        change = fid[tuple(a)] != fid[tuple(b)]
        line[tuple(a)] |= change
        line[tuple(b)] |= change
    # A plane has no second difference, whatever its slope; a jump in depth has a large
    # one. Only triples of foreground pixels count: outlines are face changes already.
    fg = maps.foreground
    d = np.where(fg, maps.view_depth, 0.0).astype(np.float64)
    for axis in (0, 1):
        lo, mid, hi = ([slice(None)] * 2 for _ in range(3))
        lo[axis], mid[axis], hi[axis] = slice(None, -2), slice(1, -1), slice(2, None)
        lo, mid, hi = tuple(lo), tuple(mid), tuple(hi)
        second = np.abs(d[lo] + d[hi] - 2.0 * d[mid])
        line[mid] |= (second > CREASE_PX * pixel_size) & fg[lo] & fg[mid] & fg[hi]
    return line


def draw_strokes(picture: np.ndarray, strokes: list[np.ndarray]) -> None:
    """Draw pixel polylines over an RGB uint8 picture in orange, anti-aliased, in place."""
    thickness = max(2, picture.shape[1] // 300)
    for s in strokes:
        pts = np.round((np.asarray(s, float).reshape(-1, 2) - 0.5) * 16).astype(np.int32)
        if len(pts):
            cv2.polylines(
                picture, [pts.reshape(-1, 1, 2)], False, STROKE_RGB, thickness, cv2.LINE_AA, 4
            )


def write_png(rgb: np.ndarray, path: str | Path) -> None:
    """Write an RGB (or grey) uint8 picture as PNG, whatever the name's extension; the file
    appears only once complete (brep/files.py).

    Raises:
        OSError: the file cannot be written.
    """
    write_atomically(path, png_bytes(rgb))


def png_bytes(rgb: np.ndarray) -> bytes:
    """An RGB (or grey) uint8 picture encoded as PNG."""
    bgr = rgb[..., ::-1] if rgb.ndim == 3 else rgb
    ok, data = cv2.imencode(".png", np.ascontiguousarray(bgr))
    if not ok:
        raise ValueError(f"cannot encode a {rgb.shape} {rgb.dtype} picture as PNG")
    return data.tobytes()


def contact_sheet(
    images: list[np.ndarray], cols: int, labels: list[str] | None = None, pad: int = 6
) -> np.ndarray:
    """Pictures on a white grid, row by row, with optional captions under them.

    Args:
        images: (H, W, 3) RGB or (H, W) grey uint8 pictures; cells take the largest
            size and smaller pictures sit in their top-left corner.
        cols: pictures per row.
        labels: one caption per picture.
        pad: white pixels between cells.
    Returns:
        (H, W, 3) uint8 RGB.
    Raises:
        ValueError: no images, or a label count that does not match.
    """
    if not images:
        raise ValueError("a contact sheet needs at least one picture")
    if labels is not None and len(labels) != len(images):
        raise ValueError(f"{len(labels)} labels for {len(images)} pictures")
    rgbs = [np.repeat(im[..., None], 3, axis=2) if im.ndim == 2 else im for im in images]
    h = max(im.shape[0] for im in rgbs)
    w = max(im.shape[1] for im in rgbs)
    cols = max(1, min(cols, len(rgbs)))
    rows = (len(rgbs) + cols - 1) // cols
    cap = 22 if labels else 0
    sheet = np.full((rows * (h + pad + cap) + pad, cols * (w + pad) + pad, 3), 255, np.uint8)
    for k, img in enumerate(rgbs):
        r, c = divmod(k, cols)
        y, x = pad + r * (h + pad + cap), pad + c * (w + pad)
        sheet[y : y + img.shape[0], x : x + img.shape[1]] = img
        if labels:
            cv2.putText(
                sheet,
                str(labels[k]),
                (x + 2, y + h + 16),
                cv2.FONT_HERSHEY_SIMPLEX,
                0.45,
                (20, 20, 20),
                1,
                cv2.LINE_AA,
            )
    return sheet
