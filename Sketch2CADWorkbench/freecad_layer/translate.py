# SPDX-License-Identifier: LGPL-2.1-or-later
"""Translatable strings, as FreeCAD's workbenches mark them: `translate(context, text)` at
run time, `QT_TRANSLATE_NOOP(context, text)` where the text is only marked (command
resources, which FreeCAD translates itself)."""

try:
    from FreeCAD import Qt

    translate = Qt.translate
    QT_TRANSLATE_NOOP = Qt.QT_TRANSLATE_NOOP
except ImportError:  # pragma: no cover (every supported FreeCAD has FreeCAD.Qt)
    from PySide import QtCore

    def translate(context: str, text: str) -> str:
        return QtCore.QCoreApplication.translate(context, text)

    def QT_TRANSLATE_NOOP(context: str, text: str) -> str:
        return text
