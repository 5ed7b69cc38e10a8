# SPDX-License-Identifier: LGPL-2.1-or-later
"""App-side proxies of Sketch2CAD's document objects, one per file (as Draft's draftobjects)."""
