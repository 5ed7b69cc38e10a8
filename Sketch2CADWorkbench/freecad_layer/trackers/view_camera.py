# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD's 3D view camera as the core's OrthoCamera, and mouse positions as its pixels.

Coin reports mouse positions in integer pixels with the origin at the bottom-left, Qt in
device-independent pixels with the origin at the top-left; the core's pixels are device
pixels with the origin at the top-left corner and pixel centres at +0.5.
"""

import numpy as np
from pivy import coin

from ...render.camera import OrthoCamera


def view_camera(view) -> OrthoCamera:
    """The view's orthographic camera, with the view's size in device pixels.

    Args:
        view: a 3D view (FreeCADGui.ActiveDocument.ActiveView).

    Returns:
        An OrthoCamera centred on the camera position, looking along its direction,
        whose scale is half the visible height (mm).

    Raises:
        ValueError: the view is perspective (the paper's pipeline is orthographic).
    """
    cam = view.getCameraNode()
    if not isinstance(cam, coin.SoOrthographicCamera):
        raise ValueError(
            "the 3D view is perspective; Sketch2CAD needs an orthographic view "
            "(View > Orthographic view)"
        )
    w, h = view.getSize()
    rot = cam.orientation.getValue()
    direction = rot.multVec(coin.SbVec3f(0, 0, -1)).getValue()
    up = rot.multVec(coin.SbVec3f(0, 1, 0)).getValue()
    # Coin renders with the default viewport mapping ADJUST_CAMERA: `height` spans the
    # view's height when it is wider than tall, and its width otherwise. (FreeCAD 0.20's
    # view.getPointOnScreen ignores the second case; the rendered image does not.)
    visible_height = cam.height.getValue() * max(1.0, h / w)
    return OrthoCamera(
        tuple(map(float, cam.position.getValue().getValue())),
        tuple(map(float, direction)),
        tuple(map(float, up)),
        visible_height / 2.0,
        int(w),
        int(h),
    )


def to_pixels(points, height: int) -> np.ndarray:
    """Coin mouse positions -> core pixels.

    Args:
        points: (N, 2) positions in device pixels, origin bottom-left (as Coin events and
            view.getPointOnScreen report them).
        height: the view's height in pixels.

    Returns:
        (N, 2) float array: the pixels' centres, origin top-left, y down.
    """
    p = np.asarray(points, float).reshape(-1, 2)
    return np.stack([p[:, 0] + 0.5, height - p[:, 1] - 0.5], axis=1)


def from_qt(position, device_pixel_ratio: float) -> tuple:
    """A Qt mouse position (device-independent pixels, origin top-left) as a core pixel."""
    x, y = position
    return x * device_pixel_ratio + 0.5, y * device_pixel_ratio + 0.5
