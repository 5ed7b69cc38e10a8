# SPDX-License-Identifier: LGPL-2.1-or-later
"""The orthographic camera shared by the renderer, data generation, fitting and FreeCAD.

Pixel convention everywhere in the core: x grows to the right, y grows downwards,
(0, 0) is the top-left corner of the top-left pixel, so pixel (i, j) of an image
array `img[j, i]` has its centre at (i + 0.5, j + 0.5). The FreeCAD layer converts
its bottom-left-origin mouse positions to this.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class OrthoCamera:
    """An orthographic view.

    Attributes:
        center: the world point (mm) at the image centre.
        direction: unit view direction, from the eye into the scene.
        up: world vector that appears upwards in the image (made orthogonal to direction).
        scale: half the visible height in mm (VTK's parallel scale).
        width, height: image size in pixels. Pixels are square.
    """

    center: Vec3
    direction: Vec3
    up: Vec3
    scale: float
    width: int = 256
    height: int = 256

    def __post_init__(self):
        d = np.asarray(self.direction, float)
        u = np.asarray(self.up, float)
        if not np.isfinite(d).all() or np.abs(d).max() < 1e-12:
            raise ValueError(f"camera direction must be a non-zero vector, got {self.direction}")
        if not np.isfinite(u).all() or not np.abs(u).any():
            raise ValueError(f"camera up must be a non-zero vector, got {self.up}")
        if np.linalg.norm(np.cross(_unit(d), _unit(u))) < 1e-9:
            raise ValueError(
                f"camera up {self.up} must not be parallel to direction {self.direction}"
            )
        if not self.scale > 0:
            raise ValueError(f"camera scale must be positive, got {self.scale}")
        if self.width <= 0 or self.height <= 0:
            raise ValueError(f"camera image size must be positive, got {self.width}x{self.height}")

    # ------------------------------------------------------------ frame
    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit (right, up, forward) vectors of the camera in world coordinates (read-only
        arrays)."""
        return self._basis

    @cached_property
    def _basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        # made once: every projection asks for it, thousands of times a sketch step
        f = _unit(np.asarray(self.direction, float))
        u = _unit(np.asarray(self.up, float))
        u = u - (u @ f) * f
        u = u / np.linalg.norm(u)
        r = np.cross(f, u)  # right-handed: right = forward x up
        for axis in (r, u, f):
            axis.flags.writeable = False
        return r, u, f

    @property
    def pixel_size(self) -> float:
        """World length (mm) of one pixel."""
        return 2.0 * self.scale / self.height

    # ------------------------------------------------------------ mapping
    def project(self, points) -> tuple[np.ndarray, np.ndarray]:
        """World points (N, 3) -> pixel positions (N, 2) and depths (N,) along direction.

        Depth is measured from the plane through `center`; larger is farther.
        """
        p = np.atleast_2d(np.asarray(points, float)) - np.asarray(self.center, float)
        r, u, f = self.basis()
        s = self.pixel_size
        x = p @ r / s + self.width / 2.0
        y = -(p @ u) / s + self.height / 2.0
        return np.stack([x, y], axis=1), p @ f

    def image_of(self, vector) -> np.ndarray:
        """The pixel displacement (2,) of a world vector (3,): projection is linear."""
        return (
            self.project(np.asarray(self.center, float) + np.asarray(vector, float))[0][0]
            - self.project(np.asarray(self.center, float))[0][0]
        )

    def unproject(self, pixels, depth=0.0) -> np.ndarray:
        """Pixel positions (N, 2) and depths (N,) or a scalar -> world points (N, 3)."""
        q = np.atleast_2d(np.asarray(pixels, float))
        r, u, f = self.basis()
        s = self.pixel_size
        a = (q[:, 0] - self.width / 2.0) * s
        b = -(q[:, 1] - self.height / 2.0) * s
        depth = np.broadcast_to(np.asarray(depth, float), (len(q),))
        return np.asarray(self.center, float) + a[:, None] * r + b[:, None] * u + depth[:, None] * f

    def ray(self, pixels) -> tuple[np.ndarray, np.ndarray]:
        """World ray origins (N, 3) on the centre plane and the shared unit direction."""
        return self.unproject(pixels, 0.0), self.basis()[2]

    def back_project_to_plane(self, pixels, plane_point, plane_normal) -> np.ndarray:
        """Pixels -> world points where their rays meet a plane (N, 3).

        Raises:
            ValueError: the plane is seen edge-on (parallel to the view direction).
        """
        o, f = self.ray(pixels)
        n = np.asarray(plane_normal, float)
        denom = float(f @ n)
        if abs(denom) < 1e-9:
            raise ValueError("the plane is seen edge-on; cannot back-project onto it")
        t = ((np.asarray(plane_point, float) - o) @ n) / denom
        return o + t[:, None] * f

    def to_dict(self) -> dict:
        """Plain JSON-ready values (the inverse of `from_dict`)."""
        return {
            "center": [float(c) for c in self.center],
            "direction": [float(c) for c in self.direction],
            "up": [float(c) for c in self.up],
            "scale": float(self.scale),
            "width": int(self.width),
            "height": int(self.height),
        }

    @staticmethod
    def from_dict(d: dict) -> OrthoCamera:
        """A camera from `to_dict` values (the constructor's checks apply)."""
        return OrthoCamera(
            tuple(d["center"]),
            tuple(d["direction"]),
            tuple(d["up"]),
            d["scale"],
            d["width"],
            d["height"],
        )

    def with_size(self, width: int, height: int) -> OrthoCamera:
        """The same view at another image size (the visible height is kept)."""
        return OrthoCamera(self.center, self.direction, self.up, self.scale, width, height)


def _unit(v: np.ndarray) -> np.ndarray:
    """v scaled to length 1; a vector whose squared length overflows or underflows (a
    direction of (1e200, 1e200, 0) is a direction) is first scaled by its largest
    component; any other is divided by its norm as it is."""
    if not 1e-150 < np.abs(v).max() < 1e150:
        v = v / np.abs(v).max()
    return v / np.linalg.norm(v)
