# SPDX-License-Identifier: LGPL-2.1-or-later
"""The Sketch2CAD model: a group holding the base box and the operations in order."""
from .feature import GROUP


class ModelFeature:
    """App::DocumentObjectGroupPython; `Tip` is the last feature, whose solid is the model's."""

    TYPE = "Sketch2CAD::Model"

    def __init__(self, obj):
        obj.Proxy = self
        obj.addProperty("App::PropertyLink", "Tip", GROUP, "The last feature: the model's solid")

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None
