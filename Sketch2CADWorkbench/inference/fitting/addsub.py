# SPDX-License-Identifier: LGPL-2.1-or-later
"""Add/subtract regression: N-gon, option, base polygon and length d (paper, Sec. 4.2)."""

from __future__ import annotations

from dataclasses import dataclass

import cadquery as cq
import numpy as np

from ...brep.faces import FaceFrame, is_curved, model_scale
from ...brep.protocol import AddSubPrism, Mode
from ...render.camera import OrthoCamera
from ..drawing import CORNER_REACH
from .common import (
    DistanceField,
    FitError,
    line_search,
    resample,
    search_range,
    stroke_pixels,
)
from .polygon import fit_polygon, is_simple, order_around_centre, profile_ends, side_corners
from .primitive import choose_option
from .refine import prism_from_ends, refine_prism
from .surface import back_project, face_frame, face_ref, option_frame

# Mean distance (px) from the far outline at the best length to its strokes above which no
# length matches: above the noisiest strokes the generator draws (see
# docs/measurements.md, addsub.PRISM_MISMATCH_PX).
PRISM_MISMATCH_PX = 20.0
# Base outline corners closer than this (px) are one corner: too few sides for N.
MIN_SIDE_PX = 2.0
# A base outline's corner lies at most this share of the model's diagonal past f's
# bounding box: a face seen nearly edge-on sends corners drawn a few pixels off it
# hundreds of millimetres away.
PAST_FACE_SHARE = 1.0


def _outline_samples(poly: np.ndarray) -> np.ndarray:
    return resample(np.concatenate([poly, poly[:1]]), 2.0)


def _past_face(corners: np.ndarray, face: cq.Face) -> float:
    """How far (mm) the corner (N, 3) farthest outside f's bounding box lies from it."""
    box = face.BoundingBox()
    low, high = np.array([box.xmin, box.ymin, box.zmin]), np.array([box.xmax, box.ymax, box.zmax])
    return float(
        np.linalg.norm(np.maximum(low - corners, 0) + np.maximum(corners - high, 0), axis=1).max()
    )


def _shortest_side(poly: np.ndarray) -> float:
    """Length of the polygon's shortest side (its units)."""
    return float(np.min(np.linalg.norm(poly - np.roll(poly, 1, axis=0), axis=1)))


def _simple_fit(corners: np.ndarray, strokes: list[np.ndarray]) -> np.ndarray:
    """The ICP-refined N-gon, or the profile end points themselves if refining made the
    polygon cross itself (noisy outlines can pull two corners past each other)."""
    poly = fit_polygon(corners, strokes)
    return poly if is_simple(poly) else order_around_centre(corners)


@dataclass(frozen=True, eq=False)
class PrismFit:
    """A prism read from its strokes, before the joint refinement of its base polygon and
    length against all of them (`refine.py`), which costs more than the rest of the fit:
    a caller that weighs several readings of the strokes refines only the one it keeps."""

    operation: AddSubPrism  # as fitted, unrefined
    base: np.ndarray  # (N, 2) its base polygon c on f, context pixels
    step: np.ndarray  # (2,) image displacement of 1 mm along its direction, pixels
    strokes: list[np.ndarray]  # every stroke of the prism (start, profile, end)
    face: cq.Face
    camera: OrthoCamera
    frame: FaceFrame
    scale: float  # the model's diagonal (mm)
    # read from one whole outline, fewer side edges drawn than it has sides
    # (`_from_one_outline`): the refinement, which pulls every line of the prism to the
    # strokes, would pull the lines left out as hidden onto those drawn
    partial: bool = False

    def refined(self) -> AddSubPrism:
        """The operation with its base polygon and length refined together against all
        the strokes (`refine_prism`), then read from the strokes' ends from there
        (`prism_from_ends`: the likeliest prism under the hand's noise); the refined one
        when that one is degenerate, and as fitted when f is curved (both fit straight
        sides) or when neither is sound (a polygon that crosses itself or has a side
        under MIN_SIDE_PX, a corner past PAST_FACE_SHARE of the model's diagonal beyond
        f, or d turned negative), or read from one outline (`partial`)."""
        if is_curved(self.face) or self.partial:
            return self.operation
        refined = refine_prism(self.base, self.operation.d, self.step, self.strokes)
        for base, d in (prism_from_ends(*refined, self.step, self.strokes), refined):
            if d > 0 and is_simple(base) and _shortest_side(base) >= MIN_SIDE_PX:
                base3d = back_project(self.camera, self.face, self.frame, base)
                if _past_face(base3d, self.face) > PAST_FACE_SHARE * self.scale:
                    continue
                return AddSubPrism(
                    self.operation.face,
                    tuple(tuple(map(float, p)) for p in base3d),
                    float(d),
                    self.operation.mode,
                )
        return self.operation


def fit_prism(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    labels: list[int],
    option: Mode | None = None,
) -> AddSubPrism:
    """Fit a right prism on f to strokes labelled start (0), profile (1) and end (2):
    `prism_fit`, refined (`PrismFit.refined`). Same arguments and errors."""
    return prism_fit(solid, face, camera, strokes, labels, option).refined()


def prism_fits(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    labels: list[int],
    option: Mode | None = None,
) -> list[PrismFit]:
    """`prism_fit`, and beside it, where three or more side edges are drawn but an
    outline drawn whole has more sides and the other outline is drawn in part
    (`_whole_outline`), the prism read from that outline (`prism_fit`'s `one_outline`):
    a designer who leaves the hidden lines out draws a hexagonal pocket's rim with the
    three side edges it does not hide and a part of its floor. Which one the strokes
    mean, their scores decide (`adapters._scored_readings`).

    Raises:
        FitError: neither reads (the first one's reason).
    """
    n = sum(1 for label in labels if label == 1)
    groups = {k: [s for s, l in zip(strokes, labels, strict=True) if l == k] for k in (0, 2)}
    ways: list[int | None] = [None]
    whole = _whole_outline(groups, CORNER_REACH * camera.width)
    if whole is not None and 3 <= n < whole[1]:
        ways.append(whole[0])
    fits, first = [], None
    for outline in ways:
        try:
            fits.append(prism_fit(solid, face, camera, strokes, labels, option, outline))
        except FitError as e:
            first = first or e
    if not fits:
        raise first or FitError("no prism reads the strokes")
    return fits


def prism_fit(
    solid: cq.Shape,
    face: cq.Face,
    camera: OrthoCamera,
    strokes: list[np.ndarray],
    labels: list[int],
    option: Mode | None = None,
    one_outline: int | None = None,
) -> PrismFit:
    """Fit a right prism on f to strokes labelled start (0), profile (1) and end (2),
    up to the joint refinement.

    N is the number of profile strokes; N-gons are fitted to the start and end strokes
    from the profile strokes' end points; the option follows from which polygon lies on
    f; d is found by line search along the prism's direction against the other outline;
    `PrismFit.refined` then refines the base polygon and d together against all the
    strokes (`refine.py`), the polygon back-projected onto f. On a curved f the corners
    are back-projected onto the surface and carried onto its tangent plane at the
    outline's centre (`surface.py`), and d is measured from that plane.

    Args:
        solid, face, camera: the context solid, base face f and context camera.
        strokes, labels: the strokes (context pixels) and their classes by counting.
        option: force the Boolean (the user's choice); None decides from the strokes.
        one_outline: read the prism from this outline (END or START) drawn whole
            (`_from_one_outline`), as with fewer than 3 side edges, however many are
            drawn.
    Raises:
        FitError: not 3 to 6 profile strokes, a missing outline, neither outline on f,
            a self-intersecting polygon, or no length matching the strokes.
    Returns:
        The fit, its AddSubPrism operation unrefined.
    """
    groups = {k: [s for s, l in zip(strokes, labels, strict=True) if l == k] for k in (0, 1, 2)}
    n = len(groups[1])
    if n > 6 or (n < 3 and is_curved(face)):
        raise FitError(
            f"a prism needs 3 to 6 profile strokes (one per side edge); {n} were recognised"
        )
    partial_d = None
    if n >= 3 and one_outline is None:
        starts, ends = profile_ends(groups[1], groups[0], groups[2])
        poly_s = _simple_fit(starts, groups[0])
        poly_e = _simple_fit(ends, groups[2])
    else:
        poly_s, poly_e, partial_d = _from_one_outline(groups, face, camera, one_outline)
        starts, ends = poly_s, poly_e
    frame = option_frame(face, camera, starts, ends)  # on a curved f: the corners drawn
    scale = model_scale(solid)
    mode = choose_option(
        face, frame, camera, _outline_samples(poly_s), _outline_samples(poly_e), option
    )
    base, other = (poly_s, groups[2]) if mode is not Mode.SUBTRACT else (poly_e, groups[0])
    if not is_simple(base):
        raise FitError("the base outline crosses itself")
    if _shortest_side(base) < MIN_SIDE_PX:
        raise FitError("two corners of the base outline coincide")
    if is_curved(face):  # its sides are curves on f: the profile strokes' ends are its corners
        base = order_around_centre(starts if mode is not Mode.SUBTRACT else ends)
    frame = face_frame(face, camera, base)  # on a curved f: T under the corners' mean
    base3d = back_project(camera, face, frame, base)
    past = _past_face(base3d, face)
    if past > PAST_FACE_SHARE * scale:
        raise FitError(
            f"the base outline runs {past:.0f} mm past the face: the view sees the face too"
            " nearly edge-on to place it"
        )
    direction = frame.normal * mode.sign
    closed = np.concatenate([base3d, base3d[:1]])
    edge_pts = np.concatenate(
        [np.linspace(closed[i], closed[i + 1], 24) for i in range(len(base3d))]
    )
    if partial_d is not None:
        d, err = partial_d
    else:
        field = DistanceField(stroke_pixels(other, (camera.height, camera.width)))
        d, err = line_search(edge_pts, direction, camera, field, search_range(scale, 0.0075, 1.5))
    if err > PRISM_MISMATCH_PX:
        raise FitError(f"no prism length matches the far outline (closest is {err:.1f} px off)")
    op = AddSubPrism(
        face_ref(face, frame), tuple(tuple(map(float, p)) for p in base3d), float(d), mode
    )
    return PrismFit(
        op,
        base,
        camera.image_of(direction),
        groups[0] + groups[1] + groups[2],
        face,
        camera,
        frame,
        scale,
        partial_d is not None,
    )


def _whole_outline(groups: dict[int, list[np.ndarray]], reach: float) -> tuple[int, int] | None:
    """The outline (its label, end or start, and its number of sides) drawn whole while
    the other one is drawn in part, as in a drawing that leaves the hidden lines out:
    one stroke per side, closing into one loop with corners `reach` pixels wide at most
    (`_closes`), the other outline with fewer strokes than that; None where there is
    none (with every line drawn, each outline has a stroke per side)."""
    for whole, other in ((2, 0), (0, 2)):
        sides = _closes(groups[whole], reach)
        if sides and len(groups[other]) < sides:
            return whole, sides
    return None


def _closes(strokes: list[np.ndarray], reach: float) -> int:
    """The number of sides of the loop the strokes close into, one per side
    (`side_corners` within `reach`), or 0 (a prism's outline has 3 to 6 sides)."""
    if not 3 <= len(strokes) <= 6:
        return 0
    try:
        return len(side_corners(strokes, reach))
    except FitError:
        return 0


def _from_one_outline(
    groups: dict[int, list[np.ndarray]],
    face: cq.Face,
    camera: OrthoCamera,
    whole: int | None = None,
) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
    """A prism drawn with fewer side edges than sides, as a designer who leaves the hidden
    lines out draws a hole (the near side edges and the near part of its floor lie behind
    the rim): its corners from the outline drawn whole, one stroke per side
    (`side_corners`; the end outline first, which the view sees whole for a boss's top and
    a hole's rim alike), the other outline that polygon moved along n_f's image. The
    length starts where the side edges drawn reach (`_reach`), or with none drawn where
    the other outline's parts lie (`_offset_to`); then the polygon and
    the length are refined together by the strokes' distances to the prism's lines alone
    (`refine_prism`, not every line: those left out as hidden have no stroke), so what
    is drawn of the far outline and the sides fixes the rest. `whole` (END or START)
    says which outline is drawn whole; None tries the end outline, then the start one.

    Returns:
        The start and end polygons (N, 2 pixels), and (d in mm, the strokes' mean
        distance to the prism's lines in pixels).
    Raises:
        FitError: no outline drawn whole, or nothing else of the prism drawn.
    """
    step = camera.image_of(FaceFrame.of(face).normal)  # pixels per mm along +n_f
    first = None
    for drawn_whole, sign in ((2, -1.0), (0, 1.0)):  # the other outline lies below the end one
        if whole is not None and drawn_whole != whole:
            continue
        try:
            poly = _simple_fit(side_corners(groups[drawn_whole]), groups[drawn_whole])
        except FitError as e:
            first = first or e
            continue
        outline, sides = groups[2 - drawn_whole], groups[1]
        if sides:
            d = _reach(sides, step)
        elif outline:  # the other outline's parts (a floor seen through the rim) alone
            d = _offset_to(outline, poly, sign * step)
        else:  # an outline's pieces alone draw no prism (a circle cut in arcs)
            raise FitError("no side edge of the prism was drawn, so its length is not known")
        drawn = groups[0] + groups[1] + groups[2]
        moved, longer = refine_prism(poly, d, sign * step, drawn, end_weight=0.0, every_line=False)
        if longer > 0 and is_simple(moved) and _shortest_side(moved) >= MIN_SIDE_PX:
            poly, d = moved, longer  # else as read before the refinement
        other = poly + sign * d * step
        lines = (np.concatenate([other, poly]), np.concatenate([np.roll(other, -1, axis=0), other]))
        err = float(_mean_distance(_samples(outline + sides), *lines))
        return (other, poly, (d, err)) if drawn_whole == 2 else (poly, other, (d, err))
    raise first or FitError("no outline of the prism was drawn whole")


def _offset_to(strokes: list[np.ndarray], poly: np.ndarray, step: np.ndarray) -> float:
    """How far (mm, > 0) the polygon (N, 2 pixels) moves along `step` (pixels per mm) to
    lie closest to the strokes (mean distance of their samples to its sides), searched
    over the span of the strokes along `step`'s image to a pixel."""
    pts, unit = _samples(strokes), step / float(np.linalg.norm(step))
    span = float((pts @ unit).max() - (poly @ unit).min()) / float(np.linalg.norm(step))
    ds = np.linspace(0.0, max(span, 0.0), max(int(span * np.linalg.norm(step)), 1) + 1)[1:]
    if not len(ds):
        raise FitError("the other outline's parts lie behind the outline drawn whole")
    moved = poly[None] + ds[:, None, None] * step
    return float(ds[np.argmin(_mean_distance(pts, moved, np.roll(moved, -1, axis=1)))])


def _reach(sides: list[np.ndarray], step: np.ndarray) -> float:
    """How far (mm) the longest side-edge stroke reaches along `step` (pixels per mm)."""
    unit = step / float(step @ step)
    return max(abs(float((np.asarray(s)[-1] - np.asarray(s)[0]) @ unit)) for s in sides)


def _samples(strokes: list[np.ndarray]) -> np.ndarray:
    """(M, 2) points every 2 pixels along the strokes."""
    return np.concatenate([resample(s, 2.0) for s in strokes])


def _mean_distance(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The points' (M, 2) mean distance to the nearest of the segments a -> b (..., S, 2),
    for each set of segments (...)."""
    ab = b - a
    rel = pts[:, None] - a[..., None, :, :]  # (..., M, S, 2)
    t = np.clip(
        np.einsum("...msk,...sk->...ms", rel, ab)
        / np.maximum((ab * ab).sum(-1), 1e-12)[..., None, :],
        0.0,
        1.0,
    )
    return np.linalg.norm(rel - t[..., None] * ab[..., None, :, :], axis=-1).min(axis=-1).mean(-1)
