# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI-side helpers over the 3D view (as Draft's trackers): the view's camera, the stroke
capture and its overlay, the preview of a reading."""
