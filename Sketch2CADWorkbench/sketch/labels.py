# SPDX-License-Identifier: LGPL-2.1-or-later
"""The curve label encodings of the paper, per operator: the C~ value of a stroke's pixels
(training targets), and the thresholds that read a regressed C back into those classes."""

from ..brep.protocol import OperatorType, per_operator

# The U-Net's classes in output order, which is also the order of its F and C heads: the
# paper's four.
CLASSES: tuple[OperatorType, ...] = (
    OperatorType.EXTRUDE,
    OperatorType.BEVEL,
    OperatorType.ADDSUB,
    OperatorType.SWEEP,
)
# The operators a data set's sample may be labelled with, in the order of its op_type
# index, which are also the structured head's classes: CLASSES first, so that data sets
# without shells read the same and the head's class logits extend the U-Net's.
LABELLED: tuple[OperatorType, ...] = CLASSES + (OperatorType.SHELL,)

EXTRUDE_OFFSET, EXTRUDE_PROFILE = 1, 0
BEVEL_L, BEVEL_L_PRIME = 1, 0
START, PROFILE, END = 0, 1, 2  # add/sub and sweep
SHELL_RIM, SHELL_WALL = 1, 0  # the inner rim drawn on f; a line down an inner wall

# C > LOW is class 1 (offset, l, profile); for add/sub and sweep C > HIGH is class 2 (end):
# the midpoints between the encodings (the paper's C > 0.5 split for two classes).
CURVE_THRESHOLDS = per_operator(
    {
        OperatorType.EXTRUDE: (0.5, float("inf")),
        OperatorType.BEVEL: (0.5, float("inf")),
        OperatorType.ADDSUB: (0.5, 1.5),
        OperatorType.SWEEP: (0.5, 1.5),
        OperatorType.SHELL: (0.5, float("inf")),
    },
    "sketch.labels.CURVE_THRESHOLDS",
)
