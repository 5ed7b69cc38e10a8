# SPDX-License-Identifier: LGPL-2.1-or-later
"""View providers of Sketch2CAD's objects (as Draft's draftviewproviders)."""
