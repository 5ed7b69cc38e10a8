# SPDX-License-Identifier: LGPL-2.1-or-later
"""A sketch's structures as the head's inputs: stroke, face and class tokens.

    feature_maps(unet, inputs) -> UNetPass            one U-Net pass, its maps kept
    tokens(logits, maps, strokes, face_id) -> Tokens  one sketch's tokens

The maps are read as if upsampled to the U-Net's internal size without upsampling them
(each pooled sum and sample is taken on the coarse map with the upsampling's weights).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import cv2
import numpy as np
import torch
import torch.nn.functional as F

from ...brep.protocol import OperatorType
from ...sketch.labels import CLASSES
from ..models import N_OPS, Sketch2CADNet

POINTS = 16  # samples along each stroke (evenly in arc length)
DECODER_LEVELS = 3  # finest decoder maps pooled (8, 16, 32 channels for the shipped net)
MAX_FACES = 48  # largest visible faces kept as tokens (a sketch sees far fewer)


STROKE_GEOMETRY = 14 + 7  # stroke_geometry and stroke_context
FACE_GEOMETRY = 5 + 2 * N_OPS
CLASS_EXTRA = 2 + N_OPS  # token counts, count_fits


ENDS = slice(2, 6)  # the ends' coordinates within stroke_geometry


def feature_channels(model: Sketch2CADNet) -> int:
    """Channels sampled per pixel: decoder maps, F and C of every operator, S, D, N."""
    return sum(model.config.widths[:-1][:DECODER_LEVELS]) + 2 * N_OPS + 5


@dataclass
class Tokens:
    """One sketch's structures as head inputs.

    stroke: (S, 2 channels + STROKE_GEOMETRY) float32; face: (K, channels +
    FACE_GEOMETRY) float32; face_ids: (K,) int64, the face-ID of each face token;
    cls: (N_OPS + CLASS_EXTRA,) float32, the U-Net's class logits, the token counts
    and which operators' drawings have this many strokes (`count_fits`);
    on_face: (S, K) float32, the share of each stroke's points on each face token;
    normal_image: (K, 2) float32, each face's mean outward normal seen in the image (x
    right, y down; its length is the sine of the angle between the normal and the view).
    """

    stroke: torch.Tensor
    face: torch.Tensor
    face_ids: torch.Tensor
    cls: torch.Tensor
    on_face: torch.Tensor
    normal_image: torch.Tensor


@dataclass
class UNetPass:
    """One pass of the U-Net over full-size inputs: its outputs at the internal size I
    and the maps the tokens pool (so a caller needing both runs the U-Net once)."""

    logits: torch.Tensor  # (B, 4) class logits
    f: torch.Tensor  # (B, 4, I, I) F logits
    c: torch.Tensor  # (B, 4, I, I) C values
    maps: list[torch.Tensor]  # (B, C_m, r_m, r_m) each at its own size r_m, channels-last:
    #                           the decoder maps (coarsest first), F and C, pooled inputs

    def sketch(self, j: int) -> list[torch.Tensor]:
        """The maps of the batch's j-th sketch, as `tokens` takes them."""
        return [m[j] for m in self.maps]


def feature_maps(model: Sketch2CADNet, x_full: torch.Tensor) -> UNetPass:
    """The U-Net's outputs and the maps the tokens pool, from full-size inputs. The
    tokens read each map as if upsampled to I (bilinear), without upsampling it: that
    and the concatenation to one tensor were 0.9 ms of a sketch's 10."""
    x = model.pool(x_full)
    logits, f, c, decoded = model.features(x)
    out = torch.cat([f, c], 1)  # F and C as the one 1x1 conv output they came from
    return UNetPass(
        logits,
        f,
        c,
        decoded[-DECODER_LEVELS:] + [out, x.contiguous(memory_format=torch.channels_last)],
    )


@functools.lru_cache(maxsize=8)
def _adjoint_taps(factor: int) -> torch.Tensor:
    """(f, 2) what each of the 2f fine pixels around a coarse pixel takes from it in
    bilinear upsampling by f along one axis (align_corners=False), 1 - |offset|: the
    first f pixels in column 0, the next f in column 1."""
    taps = 1 - ((torch.arange(2 * factor) - factor // 2 + 0.5) / factor - 0.5).abs()
    return taps.reshape(2, factor).T.contiguous()


def _upsampling_adjoint(h: torch.Tensor, factor: int) -> torch.Tensor:
    """(..., r) the adjoint of bilinear upsampling by f along the last axis, applied to
    (..., f r): each coarse pixel gathers its 2f fine pixels by the upsampling's taps,
    in blocks of f (a strided convolution, without one: conv2d took 4x as long). Taps
    past the border fold back onto the border pixels, which the upsampling clamps to."""
    pad = 3 * factor // 2  # fine pixels for the coarse pixels -1 and r past each border
    halves = F.pad(h, (pad, pad)).unflatten(-1, (-1, factor)) @ _adjoint_taps(factor)
    ext = halves[..., :-1, 0] + halves[..., 1:, 1]  # (..., r + 2)
    ext[..., 1] += ext[..., 0]  # (..., r + 2)
    ext[..., -2] += ext[..., -1]
    return ext[..., 1:-1]


def _face_sums(hits: torch.Tensor, part: torch.Tensor) -> torch.Tensor:
    """(K, C) sums over each face of a map upsampled to I (F.interpolate, bilinear):
    hits (K, I, I) the face's full-size pixels per internal cell; part (C, r, r). The
    sum of the upsampled map U p is that of p weighted by U's adjoint of the hits."""
    c, r, i = part.shape[0], part.shape[-1], hits.shape[-1]
    if r != i:
        hits = _upsampling_adjoint(
            _upsampling_adjoint(hits, i // r).transpose(1, 2), i // r
        ).transpose(1, 2)
    return hits.reshape(len(hits), r * r) @ part.permute(1, 2, 0).reshape(r * r, c)


def _fine_neighbours(
    pts: np.ndarray, size: int, internal: int
) -> tuple[torch.Tensor, torch.Tensor]:
    """Bilinear sampling at pixel points (N, 2) of the full-size maps on an I x I map,
    clamped to the border (F.grid_sample, align_corners=False, padding "border"): the
    centres of each point's 4 pixels of that map as a grid (1, N, 4, 2) and their
    weights (N, 4)."""
    t = np.clip(pts * internal / size - 0.5, 0, internal - 1)  # (N, 2) x, y
    lo = np.floor(t)
    hi = np.minimum(lo + 1, internal - 1)
    frac = t - lo
    corners = np.stack(
        [
            np.stack([lo[:, 0], lo[:, 1]], 1),
            np.stack([hi[:, 0], lo[:, 1]], 1),
            np.stack([lo[:, 0], hi[:, 1]], 1),
            np.stack([hi[:, 0], hi[:, 1]], 1),
        ],
        1,
    )
    wx, wy = frac[:, 0], frac[:, 1]
    weights = np.stack([(1 - wx) * (1 - wy), wx * (1 - wy), (1 - wx) * wy, wx * wy], 1)
    grid = (2 * corners + 1) / internal - 1
    return (
        torch.from_numpy(grid.astype(np.float32))[None],
        torch.from_numpy(weights.astype(np.float32)),
    )


def _sample(part: torch.Tensor, grid: torch.Tensor, weights: torch.Tensor) -> torch.Tensor:
    """(N, C) a map (C, r, r) upsampled to I and sampled at the points `_fine_neighbours`
    gave: the upsampled map's value at a pixel centre of I is the map's bilinear sample
    there (the same clamping at the border), so no map of size I is made."""
    at = F.grid_sample(
        part[None], grid, mode="bilinear", padding_mode="border", align_corners=False
    )[0]  # (C, N, 4)
    return (at * weights).sum(-1).T


@dataclass
class _Polylines:
    """Several polylines concatenated, for one vectorised pass over all of a sketch's
    strokes (a loop over strokes cost 1 ms a sketch): points (N, 2), each polyline's
    first and last point index, and the arc length from the first point to each point,
    counting the jump between two polylines as 1 so that each keeps its own range."""

    points: np.ndarray
    first: np.ndarray
    last: np.ndarray
    arc: np.ndarray

    @classmethod
    def of(cls, strokes: list[np.ndarray], scale: float = 1.0) -> _Polylines:
        p = [np.asarray(s, np.float64).reshape(-1, 2) for s in strokes]
        n = np.array([len(q) for q in p])
        if (n < 1).any():
            raise ValueError(f"stroke {int(np.argmin(n))} has no points")
        points = np.concatenate(p) / scale
        last = np.cumsum(n) - 1
        seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
        seg[last[:-1]] = 1.0
        return cls(points, last - n + 1, last, np.concatenate([[0.0], np.cumsum(seg)]))

    def lengths(self) -> np.ndarray:
        return self.arc[self.last] - self.arc[self.first]

    def resample(self, count: int) -> np.ndarray:
        """(S, count, 2) points evenly along each polyline's arc length (a polyline of
        no length: its first point)."""
        t = (
            self.arc[self.first][:, None]
            + np.linspace(0.0, 1.0, count)[None] * self.lengths()[:, None]
        )
        return np.stack(
            [np.interp(t, self.arc, self.points[:, 0]), np.interp(t, self.arc, self.points[:, 1])],
            -1,
        )


def stroke_geometry(strokes: list[np.ndarray], normal_xy: np.ndarray, size: int) -> np.ndarray:
    """(S, 14) per stroke, numbers that do not depend on the drawing direction: centroid
    (2), the two ends ordered by x (4), chord direction as (cos 2a, sin 2a) (2), chord
    and arc length (2), closedness (chord / arc), straightness (largest distance from
    the chord / arc), |cos| of the angle between the chord and the image of the normal
    under the stroke (a side line of an extrusion runs along it), and the length of that
    image (normal_xy: (S, 2), that image per stroke)."""
    lines = _Polylines.of(strokes, size)
    p, first, last = lines.points, lines.first, lines.last
    counts = last - first + 1
    arc = lines.lengths()
    d = p[last] - p[first]
    chord = np.linalg.norm(d, axis=1)
    u = np.where(chord[:, None] > 1e-9, d / np.maximum(chord, 1e-9)[:, None], [1.0, 0.0])
    angle = np.arctan2(u[:, 1], u[:, 0])
    across = np.repeat(np.stack([-u[:, 1], u[:, 0]], 1), counts, 0)
    off = np.maximum.reduceat(np.abs(((p - np.repeat(p[first], counts, 0)) * across).sum(1)), first)
    n = np.linalg.norm(normal_xy, axis=1)
    along = np.where(n > 1e-9, np.abs((u * normal_xy).sum(1)) / np.maximum(n, 1e-9), 0.0)
    swap = (p[first, 0] > p[last, 0]) | ((p[first, 0] == p[last, 0]) & (p[first, 1] > p[last, 1]))
    ends = np.where(
        swap[:, None],
        np.concatenate([p[last], p[first]], 1),
        np.concatenate([p[first], p[last]], 1),
    )
    centroid = np.add.reduceat(p, first) / counts[:, None]
    safe = np.maximum(arc, 1e-9)
    return np.concatenate(
        [
            centroid,
            ends,
            np.stack(
                [
                    np.cos(2 * angle),
                    np.sin(2 * angle),
                    chord,
                    arc,
                    chord / safe,
                    off / safe,
                    along,
                    n,
                ],
                1,
            ),
        ],
        1,
    ).astype(np.float32)


def stroke_context(pts: np.ndarray, face_id: np.ndarray, voted: np.ndarray) -> np.ndarray:
    """7 numbers per stroke about its neighbours: the gap from each end to the nearest
    end of another stroke, smaller first (strokes of one polygon meet end to end), the
    share of its points on each operator's most voted face (start and profile strokes
    lie on the base face, end and offset strokes leave it), and on the background.

    Args:
        pts: (S, P, 2) points along each stroke (pixels); face_id: (H, W);
        voted: (4,) face-ID the U-Net's F votes most for, per operator (-2: none).
    """
    n, size = len(pts), face_id.shape[-1]
    ends = pts[:, [0, -1]]  # (S, 2, 2)
    gap = np.full((n, 2), 1.0)
    if n > 1:
        d = np.linalg.norm(ends[:, :, None, None] - ends[None, None], axis=-1)  # S,2,S,2
        d[np.arange(n), :, np.arange(n)] = np.inf
        gap = np.sort(np.minimum(d.min((2, 3)) / size, 1.0), axis=1)
    ij = np.clip(np.floor(pts).astype(int), 0, size - 1)
    under = face_id[ij[..., 1], ij[..., 0]]  # (S, P)
    share = (under[:, :, None] == voted[None, None]).mean(1)  # (S, 4)
    return np.concatenate([gap, share, (under < 0).mean(1, keepdims=True)], 1)


# bit j of a 4-bit vote code: whether operator j's F votes for the pixel
_BIT_OF_CODE = (np.arange(1 << N_OPS)[:, None] >> np.arange(N_OPS)[None] & 1).astype(np.int64)


@functools.lru_cache(maxsize=4)
def _pixel_grid(size: int, internal: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per full-size pixel (row-major): its x, its y and the internal-size cell it falls
    in; the same for every sketch, so made once."""
    ys, xs = np.divmod(np.arange(size * size), size)
    cell = (ys * internal // size) * internal + xs * internal // size
    for a in (xs, ys, cell):
        a.flags.writeable = False
    return xs, ys, cell


def tokens(
    logits: torch.Tensor, maps: list[torch.Tensor], strokes: list[np.ndarray], face_id: np.ndarray
) -> Tokens:
    """One sketch's tokens.

    Args:
        logits: (4,) the U-Net's class logits; maps: `UNetPass.sketch` of it, each map
        (C_m, r_m, r_m), read as upsampled to the internal size I of the last.
        strokes: pixel polylines (K, 2) in the full-size maps' pixels.
        face_id: (S, S) int face index per pixel (-1 background).
    """
    i = maps[-1].shape[-1]
    size = face_id.shape[-1]
    # faces: every per-face sum is one bincount over all full-size pixels, keyed by the
    # pixel's face token + 1 (0: background or a face not kept), so no pixel selection
    flat = face_id.ravel()
    counts = np.bincount(flat + 1)[1:]  # face_id -1 (background) falls in bin 0
    ids = np.nonzero(counts)[0]
    counts = counts[ids]
    keep = np.argsort(-counts, kind="stable")[:MAX_FACES]
    ids, counts = ids[keep], counts[keep].astype(np.float32)
    k = len(ids)
    slot = np.zeros(int(face_id.max()) + 2, np.int64)  # face-ID -> token + 1; 0: none
    slot[ids] = np.arange(1, k + 1)
    key = slot[flat]  # face_id -1 reads the last entry, which is 0
    xs, ys, cell = _pixel_grid(size, i)

    def per_face(index: np.ndarray, bins: int) -> np.ndarray:
        """(k, bins) counts of the pixels of each face token per index value."""
        return np.bincount(key * bins + index, minlength=(k + 1) * bins).reshape(k + 1, bins)[1:]

    # each map's mean over the face's pixels, each pixel read from the internal-size cell
    # it falls in (a (K, I*I) count matrix times the maps)
    hits = torch.from_numpy(per_face(cell, i * i).astype(np.float32)).reshape(k, i, i)
    mean = torch.cat([_face_sums(hits, m) for m in maps], 1) / torch.from_numpy(counts)[:, None]
    c = mean.shape[1]
    # the U-Net's F votes (F logit > 0 at full size) per operator, as 4 bits per pixel;
    # OpenCV upsamples the channels-last maps as F.interpolate does (bilinear, half-pixel
    # centres) in a tenth of its time, and the four 0/1 bytes of a pixel, read as one
    # little-endian uint32, become its 4-bit code in the top byte of one product
    f_hwc = np.ascontiguousarray(maps[-2][:N_OPS].permute(1, 2, 0).numpy())
    above = cv2.resize(f_hwc, (size, size), interpolation=cv2.INTER_LINEAR) > 0
    bits = (above.view("<u4").ravel() * np.uint32(0x01020408)) >> np.uint32(24)
    votes = (per_face(bits.astype(np.int64), 1 << N_OPS) @ _BIT_OF_CODE).astype(np.float64)
    # centroid and spread from each face's pixel counts per column and per row
    coord = np.arange(size) / size
    along = np.stack([coord, coord**2], 1)  # (size, 2)
    sx, sy = per_face(xs, size) @ along, per_face(ys, size) @ along  # (k, 2) each
    centroid = np.stack([sx[:, 0], sy[:, 0]], 1) / counts[:, None]
    squares = np.stack([sx[:, 1], sy[:, 1]], 1) / counts[:, None]
    spread = np.sqrt(np.clip(squares - centroid**2, 0, None))
    geo = np.concatenate(
        [
            counts[:, None] / size**2,
            centroid,
            spread,
            votes / counts[:, None],
            votes / np.maximum(votes.sum(0), 1),
        ],
        1,
    )
    face = torch.cat([mean, torch.from_numpy(geo.astype(np.float32))], 1)
    # the faces' normals from the pooled N (the last 3 maps; stored as normal + 1); image
    # y points down
    normal_image = (mean[:, c - 3 : c - 1] - 1.0) * torch.tensor([1.0, -1.0])
    # strokes: the maps at POINTS points along each
    pts = _Polylines.of(strokes).resample(POINTS) if strokes else np.zeros((0, POINTS, 2))
    grid, weights = _fine_neighbours(pts.reshape(-1, 2), size, i)
    samples = torch.cat([_sample(m, grid, weights) for m in maps], 1).reshape(
        len(pts), POINTS, c
    )  # (S, P, C)
    normal = samples[..., -3:-1].mean(1).numpy()  # (S, 2) N_x, N_y
    # the U-Net's most voted face per operator (-2: none); image y points down, so the
    # normal's image direction is (N_x, -N_y)
    voted = np.where(votes.max(0) > 0, ids[votes.argmax(0)], -2) if k else np.full(N_OPS, -2)
    geo = (
        np.concatenate(
            [
                stroke_geometry(strokes, normal * np.array([1.0, -1.0]), size),
                stroke_context(pts, face_id, voted),
            ],
            1,
        )
        if strokes
        else np.zeros((0, STROKE_GEOMETRY), np.float32)
    )
    stroke = torch.cat([samples.mean(1), samples.amax(1), torch.from_numpy(geo)], 1)

    cls = torch.cat([logits, torch.tensor([len(strokes) / 16, k / 16, *count_fits(len(strokes))])])
    return Tokens(
        stroke.float(),
        face.float(),
        torch.from_numpy(ids.astype(np.int64)),
        cls.float(),
        stroke_on_faces(pts, face_id, ids),
        normal_image.float(),
    )


def stroke_on_faces(pts: np.ndarray, face_id: np.ndarray, ids: np.ndarray) -> torch.Tensor:
    """(S, K) share of each stroke's points (S, P, 2; pixels) on each face of `ids`."""
    size = face_id.shape[-1]
    ij = np.clip(np.floor(pts).astype(int), 0, size - 1)
    under = face_id[ij[..., 1], ij[..., 0]]  # (S, P)
    return torch.from_numpy((under[:, :, None] == ids[None, None]).mean(1).astype(np.float32))


def count_fits(strokes: int) -> list[float]:
    """Per operator (CLASSES order), 1 where its drawing has this many strokes: an
    extrusion any, a bevel its l and l', a prism 3n, a sweep 4; for the class token,
    where a sum of stroke tokens hides it."""
    fits = {
        OperatorType.EXTRUDE: True,
        OperatorType.BEVEL: strokes == 2,
        OperatorType.ADDSUB: strokes > 0 and strokes % 3 == 0,
        OperatorType.SWEEP: strokes == 4,
    }
    return [float(fits[k]) for k in CLASSES]
