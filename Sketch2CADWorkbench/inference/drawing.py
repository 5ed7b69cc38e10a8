# SPDX-License-Identifier: LGPL-2.1-or-later
"""The labellings a prism's drawing allows, from how its strokes meet.

A prism over an n-gon is drawn as 3n strokes meeting at 2n corners, three at each: the
start outline and the end outline are n-cycles of the corner graph, and the n profiles
join them corner to corner (a perfect matching between the two cycles). The corners
are found as the triples of stroke ends of three different strokes that lie closest
together (an exact cover of the ends, least total spread); the labellings are then the
few ways the corner graph splits into two n-cycles and a matching (one split for a
triangle, pentagon or hexagon, three for a quadrilateral: a cube's graph), each outline
as start or as end. The structured head (head/decode.py) chooses among them.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..sketch.labels import END, PROFILE, START

# Largest distance between two stroke ends of one corner, in image widths: level-1 noise
# moves each end by 3.6 px per axis (5.1 px RMS) on 256 px, so two ends of a corner lie
# within 14 px of each other 95% of the time; a corner's ends lie further apart than
# 30 px on 256 about never at level 1, while distinct corners may lie 5 px apart.
CORNER_REACH = 0.12
# Search nodes for the corners' exact cover before giving up (a sketch that is no prism
# may have many near-covers): on 400 level-1 sketches (seed 40001) 5000 found every cover
# 20000 did, the slowest in 0.2 s at load 10.
COVER_BUDGET = 5000


def corners(strokes: list[np.ndarray], size: int) -> np.ndarray | None:
    """(S, 2) corner index of each stroke's two ends (first, last point): the exact
    cover of all ends by triples of ends of three different strokes, within
    CORNER_REACH of each other, with the least total squared spread; None when there is
    none (or the search ran past COVER_BUDGET)."""
    ends = np.array([[s[0], s[-1]] for s in strokes], float).reshape(-1, 2)
    m, reach = len(ends), CORNER_REACH * size
    if m % 3:
        return None
    d = np.linalg.norm(ends[:, None] - ends[None], axis=-1).tolist()  # floats read faster
    # per end, the triples holding it, cheapest first, each as (cost, its ends' bitmask,
    # its ends): the search keeps the covered ends as one int (frozensets of ends were
    # most of its time)
    triples: list[list[tuple[float, int, tuple[int, int, int]]]] = [[] for _ in range(m)]
    for a in range(m):
        near = [b for b in range(a + 1, m) if d[a][b] <= reach and b // 2 != a // 2]
        for b, c in itertools.combinations(near, 2):
            if c // 2 != b // 2 and d[b][c] <= reach:
                entry = (
                    d[a][b] ** 2 + d[a][c] ** 2 + d[b][c] ** 2,
                    1 << a | 1 << b | 1 << c,
                    (a, b, c),
                )
                for e in (a, b, c):
                    triples[e].append(entry)
    for t in triples:
        t.sort()
    # a lower bound on what covering an end adds: a third of its cheapest triple
    least = [t[0][0] / 3 if t else np.inf for t in triples]
    bound = [[least[a] + least[b] + least[c] for _, _, (a, b, c) in t] for t in triples]
    best: list = [np.inf, None]
    nodes = 0
    everything = (1 << m) - 1

    def search(covered: int, chosen: list, cost: float, rest: float) -> None:
        """rest: the lower bound of the ends not yet covered (kept as a running sum:
        summing it afresh at every node was most of the search's time)."""
        nonlocal nodes
        nodes += 1
        if nodes > COVER_BUDGET or cost + rest >= best[0]:
            return
        if covered == everything:
            best[:] = [cost, list(chosen)]
            return
        free = (~covered & (covered + 1)).bit_length() - 1  # the lowest end not covered
        for (c, mask, t), low in zip(triples[free], bound[free], strict=True):
            if not covered & mask:
                search(covered | mask, chosen + [t], cost + c, rest - low)

    search(0, [], 0.0, float(sum(least)))
    if best[1] is None:
        return None
    out = np.empty(m, np.int64)
    for k, t in enumerate(best[1]):
        out[list(t)] = k
    return out.reshape(-1, 2)


def _matchings(edges: list[tuple[int, int]], vertices: int) -> list[list[int]]:
    """Every perfect matching of the graph, as lists of edge indices."""
    incident: list[list[int]] = [[] for _ in range(vertices)]
    for k, (a, b) in enumerate(edges):
        incident[a].append(k)
        incident[b].append(k)
    out: list[list[int]] = []

    def extend(used: frozenset, chosen: list[int]) -> None:
        v = next((v for v in range(vertices) if v not in used), None)
        if v is None:
            out.append(chosen)
            return
        for k in incident[v]:
            w = sum(edges[k]) - v
            if w != v and w not in used:
                extend(used | {v, w}, chosen + [k])

    extend(frozenset(), [])
    return out


def _cycles(edges: list[tuple[int, int]], chosen: list[int]) -> list[tuple[set, list[int]]]:
    """The components (vertices, edge indices) of the chosen edges, or [] unless every
    vertex has two of them (so each component is a cycle)."""
    incident: dict[int, list[int]] = {}
    for k in chosen:
        for v in edges[k]:
            incident.setdefault(v, []).append(k)
    if any(len(ks) != 2 for ks in incident.values()):
        return []
    seen: set = set()
    out = []
    for v0 in incident:
        if v0 in seen:
            continue
        stack, vs, ks = [v0], set(), set()
        while stack:
            v = stack.pop()
            if v not in vs:
                vs.add(v)
                ks.update(incident[v])
                stack += [sum(edges[k]) - v for k in incident[v]]
        seen |= vs
        out.append((vs, sorted(ks)))
    return out


def _labellings(corner: np.ndarray) -> list[np.ndarray] | None:
    """The labellings of a corner graph ((S, 2) corners of each stroke) that split it
    into two n-cycles joined corner to corner; None if it has none."""
    n = len(corner) // 3
    edges = [(int(a), int(b)) for a, b in corner]
    out = []
    for profiles in _matchings(edges, 2 * n):
        outlines = _cycles(edges, [k for k in range(len(edges)) if k not in profiles])
        if (
            len(outlines) != 2
            or any(len(vs) != n for vs, _ in outlines)
            or any(
                (edges[k][0] in outlines[0][0]) == (edges[k][1] in outlines[0][0]) for k in profiles
            )
        ):  # a profile runs from one outline to the other
            continue
        for (_, first), (_, second) in (outlines, outlines[::-1]):
            labels = np.full(len(edges), PROFILE)
            labels[first], labels[second] = START, END
            out.append(labels)
    return out or None


def prism_labellings(strokes: list[np.ndarray], size: int) -> list[np.ndarray]:
    """Every labelling (START, PROFILE, END per stroke) that the strokes' corner graph
    allows a prism's drawing; [] when they do not draw one (not 3n strokes meeting
    three at a corner, or no split into two n-cycles joined corner to corner)."""
    c = corners(strokes, size) if len(strokes) >= 9 else None
    return [] if c is None else _labellings(c) or []
