# SPDX-License-Identifier: LGPL-2.1-or-later
"""An operation's 3D sketch curves and the label encodings the networks learn: shared by
the data generator (which draws them) and the interpret pipeline (which checks a fit by
them)."""
