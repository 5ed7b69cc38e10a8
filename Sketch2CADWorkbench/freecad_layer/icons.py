# SPDX-License-Identifier: LGPL-2.1-or-later
"""Where the workbench's SVG icons are (standard library only: InitGui uses it at startup)."""

import os

ICONS = os.path.join(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "resources", "icons"
)


def icon_path(name: str) -> str:
    """The absolute path of resources/icons/<name>.svg."""
    return os.path.join(ICONS, f"{name}.svg")
