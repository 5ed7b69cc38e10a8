# SPDX-License-Identifier: LGPL-2.1-or-later
"""The networks the workbench interprets with, loaded once per FreeCAD session on first
use (torch and the weights are not needed before)."""
_PREDICTOR = None


def predictor():
    """The shipped networks (inference.weights.load_predictor), loaded on the first call."""
    global _PREDICTOR
    if _PREDICTOR is None:
        from ..inference.weights import load_predictor
        _PREDICTOR = load_predictor()
    return _PREDICTOR
