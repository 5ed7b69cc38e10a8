# SPDX-License-Identifier: LGPL-2.1-or-later
"""Training and evaluating the networks on generated data (not shipped with the workbench:
the workbench runs Sketch2CADWorkbench/inference)."""
