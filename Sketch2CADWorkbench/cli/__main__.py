# SPDX-License-Identifier: LGPL-2.1-or-later
"""`python -m Sketch2CADWorkbench.cli`: the `sketch2cad` command."""

import sys

from . import main

sys.exit(main())
