# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panels (as Draft's drafttaskpanels): the logic of a command's panel."""
