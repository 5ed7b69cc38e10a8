# SPDX-License-Identifier: LGPL-2.1-or-later
"""The head's outputs read as stroke roles and a base face."""

import numpy as np
import torch
from drawing_fixtures import prism_drawing

from Sketch2CADWorkbench.brep.protocol import OperatorType
from Sketch2CADWorkbench.inference.head.decode import choose, decode_roles, role_probabilities
from Sketch2CADWorkbench.inference.head.model import ROLES
from Sketch2CADWorkbench.sketch.labels import BEVEL_L, BEVEL_L_PRIME, CLASSES, END, PROFILE, START


def test_a_bevel_gets_exactly_one_profile_l():
    bevel = CLASSES.index(OperatorType.BEVEL)
    both_l = torch.tensor([[0.2, 0.8], [0.3, 0.7]])
    assert decode_roles(both_l[:, [1, 0]] if BEVEL_L == 0 else both_l, bevel).count(BEVEL_L) == 1
    neither = torch.tensor([[0.9, 0.1], [0.6, 0.4]])
    labels = decode_roles(neither if BEVEL_L == 1 else neither[:, [1, 0]], bevel)
    assert labels.count(BEVEL_L) == 1 and labels[1] == BEVEL_L


def test_a_prism_gets_n_start_n_profile_n_end_strokes():
    # the head reads the far outline of a 3-sided prism half as start: the counts fix it
    probs = torch.tensor(
        [[0.9, 0.05, 0.05]] * 3
        + [[0.1, 0.8, 0.1]] * 3
        + [[0.6, 0.0, 0.4], [0.55, 0.0, 0.45], [0.2, 0.0, 0.8]]
    )
    addsub = CLASSES.index(OperatorType.ADDSUB)
    assert [int(v) for v in probs.argmax(1)].count(START) == 5
    assert decode_roles(probs, addsub) == [START] * 3 + [PROFILE] * 3 + [END] * 3


def test_a_sweep_gets_one_start_two_profiles_one_end():
    probs = torch.tensor([[0.7, 0.2, 0.1], [0.1, 0.8, 0.1], [0.2, 0.7, 0.1], [0.6, 0.1, 0.3]])
    assert decode_roles(probs, CLASSES.index(OperatorType.SWEEP)) == [START, PROFILE, PROFILE, END]


def test_counts_no_drawing_has_keep_each_strokes_likeliest_role():
    probs = torch.tensor([[0.9, 0.05, 0.05]] * 4 + [[0.1, 0.1, 0.8]])
    for op in (OperatorType.ADDSUB, OperatorType.SWEEP):  # 5 strokes: neither 3n nor 4
        assert decode_roles(probs, CLASSES.index(op)) == [START] * 4 + [END]
    extrude = torch.tensor([[0.9, 0.1]] * 4)
    assert decode_roles(extrude, CLASSES.index(OperatorType.EXTRUDE)) == [0] * 4


def _two_normals() -> np.ndarray:
    """Normal images (Tokens.normal_image) of two face tokens, faces 3 and 7: face 3's
    normal points up the image and face 7's down, both seen at a slant."""
    return np.array([[0.0, -0.8], [0.0, 0.8]])


def _logits(probs: list[list[float]], op: int) -> torch.Tensor:
    """(S, 10) role logits whose operator-op probabilities are `probs`."""
    out = torch.full((len(probs), sum(ROLES)), -30.0)
    off = sum(ROLES[:op])
    out[:, off : off + ROLES[op]] = torch.tensor(probs).log()
    return out


def test_a_prism_is_read_as_its_drawing_allows():
    # the head's likeliest roles take a side edge for an outline side and that side for a
    # side edge; counts alone keep that (3 of each), the drawing's corners do not
    addsub = CLASSES.index(OperatorType.ADDSUB)
    strokes, truth = prism_drawing(3, 0, shift=(0.0, -70.0))  # the end outline above
    probs = [
        [0.8, 0.1, 0.1] if t == START else [0.1, 0.8, 0.1] if t == PROFILE else [0.1, 0.1, 0.8]
        for t in truth
    ]
    s, p = truth.index(START), truth.index(PROFILE)
    probs[s], probs[p] = [0.3, 0.6, 0.1], [0.6, 0.3, 0.1]
    faces = torch.tensor([[0.0] * 4, [0.0] * 4])
    assert decode_roles(role_probabilities(_logits(probs, addsub), addsub), addsub) != truth
    c = choose(_logits(probs, addsub), faces, addsub, strokes, _two_normals(), 256)
    assert c.roles == truth and c.face == 0  # face 3, whose normal points to the end


def test_the_end_outline_lies_from_the_start_along_the_chosen_faces_normal():
    # the head is a little surer of face 7, whose normal points away from where the
    # strokes it reads as the end outline lie: the pair of face 3 and those roles wins
    sweep = CLASSES.index(OperatorType.SWEEP)
    t = np.linspace(0, 2 * np.pi, 40)
    ring = np.stack([30 * np.cos(t), 10 * np.sin(t)], 1)
    strokes = [
        ring + (128, 180),
        np.array([[98.0, 180.0], [98.0, 100.0]]),
        np.array([[158.0, 180.0], [158.0, 100.0]]),
        ring + (128, 100),
    ]
    sure = [[0.9, 0.05, 0.05], [0.05, 0.9, 0.05], [0.05, 0.9, 0.05], [0.05, 0.05, 0.9]]
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.5]])
    c = choose(_logits(sure, sweep), faces, sweep, strokes, _two_normals(), 256)
    assert c.roles == [START, PROFILE, PROFILE, END] and c.face == 0
    # and where the head is sure of face 7 but not of which circle starts, the face
    # says: the circle up the image (along face 7's normal, down) is the start
    unsure = [[0.45, 0.1, 0.45], sure[1], sure[2], [0.45, 0.1, 0.45]]
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 5.0]])
    c = choose(_logits(unsure, sweep), faces, sweep, strokes, _two_normals(), 256)
    assert c.roles == [END, PROFILE, PROFILE, START] and c.face == 1


def test_a_bevels_copy_lies_from_its_profile_along_the_crease_down_the_chosen_faces_normal():
    # l' is l moved along the crease, -n_f. The head is surer of face 1 with the lower
    # stroke as l; from there the upper stroke lies 45 degrees off -n_1's image (face 1's
    # normal points down-left), which a crease cannot do: face 0 (normal up the image)
    # with the upper stroke as l is read instead
    bevel = CLASSES.index(OperatorType.BEVEL)
    x = np.linspace(-20.0, 20.0, 20)
    arc = np.stack([120.0 + x, 90.0 + 0.02 * x**2], 1)
    strokes = [arc, arc + (0.0, 80.0)]  # l on top, l' 80 px below it
    normals = np.array([[0.0, -0.8], [-0.57, 0.57]])
    lower_as_l = [[0.6, 0.4], [0.3, 0.7]]  # (l', l) probabilities per stroke
    faces = torch.tensor([[0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    alone = choose(_logits(lower_as_l, bevel), faces, bevel, strokes, np.zeros((2, 2)), 256)
    assert alone.roles == [BEVEL_L_PRIME, BEVEL_L] and alone.face == 1  # head-on: no tie
    c = choose(_logits(lower_as_l, bevel), faces, bevel, strokes, normals, 256)
    assert c.roles == [BEVEL_L, BEVEL_L_PRIME] and c.face == 0
