# SPDX-License-Identifier: LGPL-2.1-or-later
"""Structured heads: the shipped U-Net's features read per stroke and per face.

The pipeline knows more than pixels: the strokes are known polylines and the B-rep faces
are known through the face-ID map. The per-pixel U-Net (models.py) must find both again,
and its regressed C hedges between the add/sub and sweep classes (its mean C by true
class is 0.67 / 0.99 / 1.33 for labels 0 / 1 / 2). These heads take its frozen
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

The modules, in the order a sketch goes through them:

    tokens.py      the U-Net's pass and the stroke, face and class tokens
    model.py       the transformer (HeadConfig, StructureHead) and batching
    decode.py      the outputs read as stroke roles and a base face (`choose`)
    paint.py       the choice painted into F and C
    checkpoint.py  saving and loading a head
    predictor.py   the interpret pipeline's Predictor with the head
"""
