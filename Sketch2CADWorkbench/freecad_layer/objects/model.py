# SPDX-License-Identifier: LGPL-2.1-or-later
"""The Sketch2CAD model: a group holding the base box and the operations in order."""

from .feature import BASE, Proxy


class ModelFeature(Proxy):
    """Proxy of an App::DocumentObjectGroupPython whose `Tip` is the last feature.

    A group rather than a Part feature: each step is a Part feature with its own solid
    (as in PartDesign), so the model's solid is its Tip's Shape and is not computed or
    drawn a second time; the tree shows the steps in order under the model.
    """

    TYPE = "Sketch2CAD::Model"

    def __init__(self, obj):
        obj.Proxy = self
        obj.addProperty("App::PropertyLink", "Tip", BASE, "The last feature: the model's solid")
