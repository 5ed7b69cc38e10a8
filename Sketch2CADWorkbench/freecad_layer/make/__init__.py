# SPDX-License-Identifier: LGPL-2.1-or-later
"""make_* functions shared by the GUI commands and the tests (as Draft's draftmake)."""
