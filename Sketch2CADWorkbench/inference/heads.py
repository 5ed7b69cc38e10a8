# SPDX-License-Identifier: LGPL-2.1-or-later
"""Structured heads: the shipped U-Net's features read per stroke and per face.

The pipeline knows more than pixels: the strokes are known polylines and the B-rep faces
are known through the face-ID map. The per-pixel U-Net (models.py) must find both again,
and its regressed C hedges between the add/sub and sweep classes (docs/NOTES.md: C by
true class 0.67 / 0.99 / 1.33 for labels 0 / 1 / 2). These heads take its frozen
features and decide per structure:

    stroke token   the U-Net's decoder maps (3 finest levels), its F and C outputs and
                   the inputs S, D, N, sampled at POINTS points along the stroke, mean-
                   and max-pooled; plus the stroke's geometry (centroid, chord, length,
                   closedness, straightness, angle to the image of the normal under it)
    face token     the same maps mean-pooled over the face's visible pixels (face-ID
                   map), plus its area, centroid, extent and the U-Net's F votes on it
    class token    the U-Net's class logits and the token counts
      -> a small transformer over all tokens (stroke-to-stroke and stroke-to-face
         context: which stroke ends where another starts, which face the strokes rest on)
      -> per operator: each stroke's role (extrude offset / profile, bevel l / l',
         add/sub and sweep start / profile / end), each face's logit of being f, and
         a correction of the operator logits.

Painted back into the F and C maps (`paint_face`, `paint_curve`), the choices are scored
by the paper's face IoU and curve accuracy unchanged, so the figures stay comparable with
Table 1 and with the U-Net's own row (training/heads.py prints both).

Why frozen features: a head over them trains in minutes on a CPU, where retraining the
U-Net takes hours; and the U-Net's maps are already right about where the base face is
and which part of a profile points along n_f, only not about whole strokes.
"""

from __future__ import annotations

import functools
import hashlib
import itertools
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import cv2
import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F
from scipy.optimize import linear_sum_assignment

from ..brep.files import atomic_path
from ..brep.protocol import OperatorType
from ..render.strokes import rasterize
from ..sketch.labels import BEVEL_L, BEVEL_L_PRIME, CLASSES, END, START
from .drawing import prism_labellings
from .fitting.stroke_roles import MIN_SIN
from .models import N_OPS, Sketch2CADNet, load_checkpoint
from .weights import NetworkPredictor, resolve

HEAD_FORMAT = "sketch2cad-head"
POINTS = 16  # samples along each stroke (evenly in arc length)
DECODER_LEVELS = 3  # finest decoder maps pooled (8, 16, 32 channels for the shipped net)
MAX_FACES = 48  # largest visible faces kept as tokens (a sketch sees far fewer)
# Stroke roles per operator (the curve label encodings of sketch/labels.py).
ROLES = (2, 2, 3, 3)
ROLE_OFFSETS = tuple(int(v) for v in np.cumsum((0, *ROLES[:-1])))
STROKE_GEOMETRY = 14 + 7  # stroke_geometry and stroke_context
FACE_GEOMETRY = 5 + 2 * N_OPS
CLASS_EXTRA = 2 + N_OPS  # token counts, count_fits
# Gaps between stroke ends (image widths) that the end bias tells apart: level-3 noise
# moves an end by about 0.03, the sides of a small prism are about 0.1 long.
END_GAP_BINS = (0.01, 0.02, 0.04, 0.08, 0.16)
ENDS = slice(2, 6)  # the ends' coordinates within stroke_geometry
# Shares of a stroke's points on a face that the face bias tells apart: none, a corner's
# worth, part, most, all (a start stroke lies on the base face, an end stroke leaves it).
ON_FACE_BINS = (0.05, 0.35, 0.65, 0.95)


def feature_channels(model: Sketch2CADNet) -> int:
    """Channels sampled per pixel: decoder maps, F and C of every operator, S, D, N."""
    return sum(model.config.widths[:-1][:DECODER_LEVELS]) + 2 * N_OPS + 5


@dataclass
class HeadConfig:
    """The head's settings; saved in its checkpoint, so a file rebuilds the head."""

    channels: int = 69  # feature_channels of the U-Net it reads
    width: int = 96
    layers: int = 3
    attention_heads: int = 4
    dropout: float = 0.1
    end_bias: bool = True  # attention between strokes biased by how near their ends lie
    face_bias: bool = True  # attention between a stroke and a face by how much it lies on it


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


# ---------------------------------------------------------------- features
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


# ---------------------------------------------------------------- the head
class AttentionLayer(nn.Module):
    """A pre-norm transformer layer whose attention adds a (B, heads, L, L) bias. Not
    torch's TransformerEncoderLayer: its fused inference path reads a per-sample 3-D
    mask otherwise than its training path (outputs differed by 0.6 in eval mode)."""

    def __init__(self, width: int, heads: int, dropout: float):
        super().__init__()
        self.heads, self.dropout = heads, dropout
        self.norm1, self.norm2 = nn.LayerNorm(width), nn.LayerNorm(width)
        self.qkv = nn.Linear(width, 3 * width)
        self.out = nn.Linear(width, width)
        self.feed = nn.Sequential(
            nn.Linear(width, 2 * width), nn.ReLU(), nn.Dropout(dropout), nn.Linear(2 * width, width)
        )
        self.drop = nn.Dropout(dropout)

    def forward(self, h: torch.Tensor, bias: torch.Tensor) -> torch.Tensor:
        """(B, L, width) tokens, (B, heads, L, L) bias -> (B, L, width)."""
        b, n, w = h.shape
        q, k, v = (
            self.qkv(self.norm1(h))
            .view(b, n, 3, self.heads, w // self.heads)
            .permute(2, 0, 3, 1, 4)
        )
        a = F.scaled_dot_product_attention(
            q, k, v, attn_mask=bias, dropout_p=self.dropout if self.training else 0.0
        )
        h = h + self.drop(self.out(a.transpose(1, 2).reshape(b, n, w)))
        return h + self.drop(self.feed(self.norm2(h)))


class StructureHead(nn.Module):
    """Transformer over one class token, the stroke tokens and the face tokens."""

    def __init__(self, config: HeadConfig | None = None):
        super().__init__()
        self.config = cfg = config or HeadConfig()
        w = cfg.width
        self.embed_cls = nn.Linear(N_OPS + CLASS_EXTRA, w)
        self.embed_stroke = nn.Sequential(
            nn.LayerNorm(2 * cfg.channels + STROKE_GEOMETRY),
            nn.Linear(2 * cfg.channels + STROKE_GEOMETRY, w),
        )
        self.embed_face = nn.Sequential(
            nn.LayerNorm(cfg.channels + FACE_GEOMETRY), nn.Linear(cfg.channels + FACE_GEOMETRY, w)
        )
        # layers = 0: every token read alone (the ablation of the context)
        self.layers = nn.ModuleList(
            AttentionLayer(w, cfg.attention_heads, cfg.dropout) for _ in range(cfg.layers)
        )
        # per attention head, a learned bias per END_GAP_BINS bin of two strokes' end gap:
        # the strokes of one outline meet end to end, which attention over coordinates
        # finds only approximately (ablation: docs/NOTES.md, stop 22)
        self.end_bias = (
            nn.Embedding(len(END_GAP_BINS) + 1, cfg.attention_heads)
            if cfg.end_bias and cfg.layers
            else None
        )
        # and per bin of a stroke's share on a face, a bias each way (stroke to face, face
        # to stroke): which face a stroke lies on is in no token
        self.face_bias = (
            nn.Embedding(len(ON_FACE_BINS) + 1, 2 * cfg.attention_heads)
            if cfg.face_bias and cfg.layers
            else None
        )
        for bias in (self.end_bias, self.face_bias):
            if bias is not None:
                nn.init.zeros_(bias.weight)
        self.norm = nn.LayerNorm(w)
        self.cls_out = nn.Linear(w, N_OPS)
        self.role_out = nn.Linear(w, sum(ROLES))
        self.face_out = nn.Linear(w, N_OPS)
        with torch.no_grad():  # start as the U-Net's classifier: a correction of its logits
            self.cls_out.weight.zero_()
            self.cls_out.bias.zero_()

    def _attention_bias(
        self, stroke: torch.Tensor, on_face: torch.Tensor, pad: torch.Tensor
    ) -> torch.Tensor:
        """(B, heads, L, L) additive attention mask: -inf on padded keys; between strokes
        the end bias of their nearest ends' gap bin; between a stroke and a face the face
        bias of the stroke's share on it."""
        b, n_s, heads = stroke.shape[0], stroke.shape[1], self.config.attention_heads
        n = pad.shape[1]
        mask = torch.zeros(b, heads, n, n).masked_fill(pad[:, None, None], float("-inf"))
        if self.end_bias is not None:
            geo = 2 * self.config.channels
            ends = stroke[..., geo + ENDS.start : geo + ENDS.stop].reshape(b, n_s, 2, 2)
            gap = (ends[:, :, None, :, None] - ends[:, None, :, None, :]).norm(dim=-1)
            bins = torch.bucketize(gap.amin((-2, -1)), torch.tensor(END_GAP_BINS))
            mask[:, :, 1 : 1 + n_s, 1 : 1 + n_s] += self.end_bias(bins).permute(0, 3, 1, 2)
        if self.face_bias is not None:
            bias = self.face_bias(torch.bucketize(on_face, torch.tensor(ON_FACE_BINS)))
            mask[:, :, 1 : 1 + n_s, 1 + n_s :] += bias[..., :heads].permute(0, 3, 1, 2)
            mask[:, :, 1 + n_s :, 1 : 1 + n_s] += bias[..., heads:].permute(0, 3, 2, 1)
        return mask

    def forward(
        self,
        cls: torch.Tensor,
        stroke: torch.Tensor,
        stroke_mask: torch.Tensor,
        face: torch.Tensor,
        face_mask: torch.Tensor,
        on_face: torch.Tensor,
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Padded batch -> logits.

        Args:
            cls: (B, N_OPS + CLASS_EXTRA); stroke: (B, S, Ds), stroke_mask: (B, S) bool
            (True = real); face: (B, K, Df), face_mask: (B, K) bool; on_face: (B, S, K)
            each stroke's share on each face.
        Returns:
            class logits (B, 4) (the U-Net's plus a correction); role logits (B, S, 10)
            (operator k's roles at ROLE_OFFSETS[k]); face logits (B, K, 4) (-inf on padding).
        """
        n_s = stroke.shape[1]
        h = torch.cat(
            [self.embed_cls(cls)[:, None], self.embed_stroke(stroke), self.embed_face(face)], 1
        )
        pad = torch.cat([torch.zeros_like(stroke_mask[:, :1]), ~stroke_mask, ~face_mask], 1)
        if len(self.layers):
            bias = self._attention_bias(stroke, on_face, pad)
            for layer in self.layers:
                h = layer(h, bias)
        h = self.norm(h)
        logits = cls[:, :N_OPS] + self.cls_out(h[:, 0])
        roles = self.role_out(h[:, 1 : 1 + n_s])
        faces = self.face_out(h[:, 1 + n_s :]).masked_fill(~face_mask[..., None], float("-inf"))
        return logits, roles, faces


def collate(items: list[Tokens]) -> tuple[torch.Tensor, ...]:
    """Tokens of several sketches -> the padded batch StructureHead.forward takes."""
    b = len(items)
    n_s = max(1, max(len(t.stroke) for t in items))
    n_f = max(1, max(len(t.face) for t in items))
    stroke = torch.zeros(b, n_s, items[0].stroke.shape[1])
    face = torch.zeros(b, n_f, items[0].face.shape[1])
    s_mask = torch.zeros(b, n_s, dtype=torch.bool)
    f_mask = torch.zeros(b, n_f, dtype=torch.bool)
    on_face = torch.zeros(b, n_s, n_f)
    for j, t in enumerate(items):
        stroke[j, : len(t.stroke)], s_mask[j, : len(t.stroke)] = t.stroke, True
        face[j, : len(t.face)], f_mask[j, : len(t.face)] = t.face, True
        on_face[j, : len(t.stroke), : len(t.face)] = t.on_face
    return torch.stack([t.cls for t in items]), stroke, s_mask, face, f_mask, on_face


# ---------------------------------------------------------------- decoding
def role_probabilities(roles: torch.Tensor, op: int) -> torch.Tensor:
    """(S, 10) role logits of one sketch -> (S, ROLES[op]) probabilities of operator op."""
    return roles[:, ROLE_OFFSETS[op] : ROLE_OFFSETS[op] + ROLES[op]].softmax(-1)


def role_counts(op: int, strokes: int) -> tuple[int, ...] | None:
    """How many strokes take each role (curve label order) in a sketch of `strokes`
    strokes of operator op, where the operator's drawing fixes it: a bevel has exactly
    one profile l (paper, Fig. 7); a prism over an n-gon has n start, n profile and n end
    strokes; a sweep its start and end ellipses joined by 2 profiles. None: not fixed
    (an extrusion's offset strokes vary with the face), or a count the drawing cannot
    have (then each stroke takes its own likeliest role)."""
    kind = CLASSES[op]
    if kind is OperatorType.BEVEL and strokes:
        counts = [strokes - 1, strokes - 1]
        counts[BEVEL_L] = 1
        return tuple(counts)
    if kind is OperatorType.ADDSUB and strokes and strokes % 3 == 0:
        return (strokes // 3,) * 3
    if kind is OperatorType.SWEEP and strokes == 4:
        return (1, 2, 1)
    return None


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


def decode_roles(probs: torch.Tensor, op: int) -> list[int]:
    """Each stroke's curve label: the most likely labelling with `role_counts` strokes
    per role (an assignment of strokes to role slots), else each stroke's argmax. The
    counts turn a prism whose far outline the head half reads as start into n and n."""
    if not len(probs):
        return []
    counts = role_counts(op, len(probs))
    if counts is None:
        return [int(v) for v in probs.argmax(1)]
    slots = np.repeat(np.arange(len(counts)), counts)
    cost = -np.log(np.clip(probs.numpy()[:, slots], 1e-12, None))  # (strokes, slots)
    rows, cols = linear_sum_assignment(cost)
    labels = np.empty(len(probs), np.int64)
    labels[rows] = slots[cols]
    return [int(v) for v in labels]


@dataclass
class Choice:
    """The head's reading of one sketch under one operator."""

    roles: list[int]  # each stroke's curve label
    face: int  # the chosen face token (index into face_ids); -1: no face in view


# The two outlines each operator's drawing ties to n_f: (from, to, sign), the `to` outline
# lying from the `from` one along sign * n_f: a prism's or sweep's end outline from its
# start (sketch/curves.py orders them along n_f), a bevel's l' from l along its crease,
# which runs along -n_f (brep/corners.py CREASE_COS).
OUTLINES = {
    OperatorType.ADDSUB: (START, END, 1.0),
    OperatorType.SWEEP: (START, END, 1.0),
    OperatorType.BEVEL: (BEVEL_L, BEVEL_L_PRIME, -1.0),
}
# The least cosine between the image shift from one outline to the other (stroke
# midpoints) and sign * n_f's image that agrees. A bevel's copy l' is the whole stroke
# moved, so the shift keeps the crease's direction: 0.9 accepts 99% of the truths at
# noise level 3 (a validation set of seed 30017: 1% quantile .928; every one at level 1,
# heldout-l1c's lowest .985; docs/NOTES.md stop 33). A prism's or a sweep's outlines are
# drawn side by side or as ellipses, whose midpoints the hand moves more (a short sweep's
# truth reaches -0.86 at level 3): the sign alone.
OUTLINE_SHIFT_COS = {OperatorType.ADDSUB: 0.0, OperatorType.SWEEP: 0.0, OperatorType.BEVEL: 0.9}


def _outline_labellings(op: int, strokes: list[np.ndarray], size: int) -> list[np.ndarray]:
    """The labellings a drawing of op with two outlines allows: a prism's from how its
    strokes meet (drawing.py), a sweep's any 1 / 2 / 1 split of its 4 strokes, a bevel's
    either of its 2 strokes as l (`count_fits`)."""
    kind = CLASSES[op]
    if kind is OperatorType.ADDSUB:
        return prism_labellings(strokes, size)
    if kind is OperatorType.SWEEP and len(strokes) == 4:
        return [np.array(p) for p in sorted(set(itertools.permutations((0, 1, 1, 2))))]
    if kind is OperatorType.BEVEL and len(strokes) == 2:
        return [np.array([BEVEL_L, BEVEL_L_PRIME]), np.array([BEVEL_L_PRIME, BEVEL_L])]
    return []


def choose(
    role_logits: torch.Tensor,
    face_logits: torch.Tensor,
    op: int,
    strokes: list[np.ndarray],
    normal_image: np.ndarray,
    size: int,
) -> Choice:
    """The stroke roles and the base face, read together where the drawing ties them.

    A prism's or sweep's end outline lies from its start outline along n_f, a bevel's l'
    from its l along -n_f (OUTLINES), so in the image the one lies from the other along
    n_f's image, within OUTLINE_SHIFT_COS: the likeliest pair of a face and a labelling
    the drawing allows that agree so is chosen (log-probabilities summed). A face seen
    head-on (its normal's image shorter than MIN_SIN) agrees with any labelling. Where
    the drawing allows no such labelling (an extrusion, not a prism's corner graph) or
    none agrees with any face: `decode_roles` and the likeliest face, each alone.

    Args:
        role_logits: (S, 10) and face_logits: (K, 4), the head's outputs for one sketch;
        strokes: its S polylines (pixels); normal_image: (K, 2) each face token's
        normal seen in the image (Tokens.normal_image); size: the maps' side (pixels).
    """
    probs = role_probabilities(role_logits, op)
    face_lp = face_logits[: len(normal_image), op].log_softmax(0).numpy()
    alone = Choice(decode_roles(probs, op), int(face_lp.argmax()) if len(face_lp) else -1)
    labellings = _outline_labellings(op, strokes, size)
    if not labellings or not len(face_lp):
        return alone
    labels = np.stack(labellings)  # (L, S)
    role_lp = np.log(np.clip(probs.numpy(), 1e-12, None))
    score = role_lp[np.arange(len(strokes))[None], labels].sum(1)[:, None] + face_lp[None]
    first, second, sign = OUTLINES[CLASSES[op]]
    mids = np.stack([np.asarray(s, float).reshape(-1, 2).mean(0) for s in strokes])
    shift = np.stack(
        [mids[lab == second].mean(0) - mids[lab == first].mean(0) for lab in labels]
    )  # (L, 2)
    n_img = sign * np.asarray(normal_image, np.float64)  # (K, 2)
    n_len = np.linalg.norm(n_img, axis=1)
    cos = shift @ n_img.T / np.maximum(np.linalg.norm(shift, axis=1)[:, None] * n_len, 1e-12)
    agree = (cos > OUTLINE_SHIFT_COS[CLASSES[op]]) | (n_len < MIN_SIN)[None]
    score = np.where(agree, score, -np.inf)  # (L, K)
    if not np.isfinite(score).any():
        return alone
    lab, face = np.unravel_index(int(score.argmax()), score.shape)
    return Choice([int(v) for v in labels[lab]], int(face))


def paint_curve(strokes: list[np.ndarray], labels: list[int], size: int) -> np.ndarray:
    """C: each stroke's pixels carry its label, drawn as the data generator draws C~
    (datagen/strokes.py: the later stroke wins where strokes cross)."""
    return rasterize(strokes, size, size, [float(v) for v in labels])


def paint_face(
    face_probs: torch.Tensor, face_ids: torch.Tensor, face_id: np.ndarray, chosen: int
) -> np.ndarray:
    """F: 1 on the chosen face's pixels (index into face_ids); every other face gets at
    most 0.5 p / p_max (not above the 0.5 that counts as f, so the paper's IoU and the
    fitting's vote see one face, while the fitting's fallback order by mean F follows
    the head's probabilities)."""
    out = np.zeros(face_id.shape, np.float32)
    if not len(face_ids):
        return out
    p = face_probs.numpy()
    value = 0.5 * p / max(p.max(), 1e-12)
    value[chosen] = 1.0
    lut = np.zeros(int(face_id.max()) + 2, np.float32)  # its last entry (0) for -1
    lut[face_ids.numpy()] = value
    return lut[face_id]


def painted(
    role_logits: torch.Tensor,
    face_logits: torch.Tensor,
    op: int,
    strokes: list[np.ndarray],
    t: Tokens,
    face_id: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The head's reading of one sketch under operator op (`choose`) painted into the F
    and C maps the fitting and the paper's metrics read (`paint_face`, `paint_curve`).

    Args:
        role_logits: (S, 10), face_logits: (K', 4) the head's outputs (K' >= K: padded);
        strokes: the S polylines; t: the sketch's tokens; face_id: (H, W) face-ID map.
    """
    c = choose(role_logits, face_logits, op, strokes, t.normal_image.numpy(), face_id.shape[-1])
    return (
        paint_face(face_logits[: len(t.face_ids), op].softmax(0), t.face_ids, face_id, c.face),
        paint_curve(strokes, c.roles, face_id.shape[-1]),
    )


# ---------------------------------------------------------------- checkpoints
def save_head(path: str | Path, head: StructureHead, **extra) -> None:
    """The head's weights and config (plus `extra`), written atomically."""
    with atomic_path(path) as tmp:
        torch.save(
            {
                "format": HEAD_FORMAT,
                "config": asdict(head.config),
                "model": head.state_dict(),
                **extra,
            },
            tmp,
        )


def load_head(path: str | Path) -> tuple[StructureHead, dict]:
    """A head (eval mode) and its checkpoint dictionary. Raises ValueError for a file
    that is not a head checkpoint. A pickle: load only the project's own files."""
    try:
        ckpt = torch.load(path, map_location="cpu", weights_only=False)
    except FileNotFoundError:
        raise
    except Exception as e:
        raise ValueError(
            f"{path}: not a readable {HEAD_FORMAT} checkpoint ({type(e).__name__}: {str(e)[:120]})"
        ) from None
    if not isinstance(ckpt, dict) or ckpt.get("format") != HEAD_FORMAT:
        raise ValueError(f"{path}: not a {HEAD_FORMAT} checkpoint")
    known = {f.name for f in fields(HeadConfig)}
    head = StructureHead(HeadConfig(**{k: v for k, v in ckpt["config"].items() if k in known}))
    head.load_state_dict(ckpt["model"])
    return head.eval(), ckpt


# ---------------------------------------------------------------- the predictor
class StructuredPredictor(NetworkPredictor):
    """The interpret pipeline's Predictor with the head's choices in F and C.

    `observe(strokes, face_id)` hands over the structures of the sketch about to be
    classified (the context camera's stroke polylines and face-ID map: interpret's
    Context.strokes and Context.maps.face_id); `classify` and `segment` then answer with
    the head's class probabilities and the painted maps, and `stroke_roles` and
    `face_probabilities` expose the per-stroke and per-face probabilities behind them.
    The first inputs after `observe` are taken as that sketch's; without `observe`, or
    for other inputs after them, it answers as the plain U-Net predictor.
    """

    def __init__(self, model: Sketch2CADNet, head: StructureHead, threads: int | None = 2):
        super().__init__(model, threads)
        self.head = head.eval()
        self._strokes: list[np.ndarray] | None = None
        self._face_id: np.ndarray | None = None
        self._head_out = None  # (inputs, tokens, class probs, role logits, face logits)

    def observe(self, strokes: list[np.ndarray], face_id: np.ndarray) -> None:
        """The next sketch's stroke polylines (pixels of the maps) and face-ID map."""
        self._strokes = [np.asarray(s, float) for s in strokes]
        self._face_id = np.asarray(face_id)
        self._head_out = None

    def _structured(self, inputs: np.ndarray):
        if self._strokes is None:
            return None
        if self._head_out is not None and self._head_out[0] is not inputs:
            return None  # another sketch's inputs than the observed one: the U-Net alone
        if self._head_out is None:  # the first inputs since `observe` are its sketch's
            if self.threads:
                torch.set_num_threads(self.threads)
            x = torch.from_numpy(np.ascontiguousarray(inputs, dtype=np.float32))[None]
            with torch.inference_mode():  # the model is in eval mode since __init__
                u = feature_maps(self.model, x)
                t = tokens(u.logits[0], u.sketch(0), self._strokes, self._face_id)
                cls, roles, faces = self.head(*collate([t]))
            self._head_out = (inputs, t, cls[0].softmax(0).numpy(), roles[0], faces[0])
        return self._head_out

    def classify(self, inputs: np.ndarray) -> np.ndarray:
        out = self._structured(inputs)
        return super().classify(inputs) if out is None else out[2]

    def stroke_roles(self, inputs: np.ndarray, op_type: OperatorType) -> np.ndarray:
        """(S, roles) probabilities of each observed stroke's role under op_type, in the
        curve label order of sketch/labels.py."""
        out = self._structured(inputs)
        if out is None:
            raise ValueError("stroke_roles needs observe(strokes, face_id) first")
        return role_probabilities(out[3], CLASSES.index(op_type)).numpy()

    def face_probabilities(self, inputs: np.ndarray, op_type: OperatorType) -> dict[int, float]:
        """Face-ID -> probability of being the base face under op_type (visible faces)."""
        out = self._structured(inputs)
        if out is None:
            raise ValueError("face_probabilities needs observe(strokes, face_id) first")
        p = out[4][:, CLASSES.index(op_type)].softmax(0)
        return {int(i): float(v) for i, v in zip(out[1].face_ids, p, strict=False)}

    def segment(self, inputs: np.ndarray, op_type: OperatorType) -> tuple[np.ndarray, np.ndarray]:
        out = self._structured(inputs)
        if out is None:
            return super().segment(inputs, op_type)
        k = CLASSES.index(op_type)
        return painted(out[3], out[4], k, self._strokes, out[1], self._face_id)


def load_structured_predictor(
    head_path: str | Path, weights: str | Path | None = None
) -> StructuredPredictor:
    """The U-Net of `weights` (default: shipped) with the head of `head_path`.

    Raises:
        ValueError: the head was trained on another U-Net's features (or does not say
            on which: it records the U-Net's SHA-256).
    """
    path = resolve(weights)
    model, _ = load_checkpoint(path)
    head, ckpt = load_head(head_path)
    # the head reads the U-Net's inner features, which another U-Net lays out otherwise
    if ckpt.get("unet_sha256") != sha256_of(path):
        raise ValueError(
            f"{head_path} was trained on the features of another U-Net "
            f"({ckpt.get('unet')}), not {path}"
        )
    return StructuredPredictor(model, head)


def sha256_of(path: str | Path) -> str:
    """The hex SHA-256 of a file (which U-Net a head was trained on)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()
