# SPDX-License-Identifier: LGPL-2.1-or-later
"""An OCCT build run apart hands its shape back, and its crash or hang is a failed build,
not the end of the process that asked for it."""

import os
import signal
import time

import cadquery as cq

from Sketch2CADWorkbench.brep.apart import built_apart


def test_a_shape_built_apart_comes_back_whole():
    box = cq.Solid.makeBox(40, 30, 20)
    got = built_apart(lambda: box, 10.0)
    assert got is not None and abs(got.Volume() - 24000) < 1e-6
    assert len(got.Faces()) == 6
    assert built_apart(lambda: None, 10.0) is None


def test_where_the_system_cannot_fork_the_shape_is_built_here(monkeypatch):
    box = cq.Solid.makeBox(40, 30, 20)
    monkeypatch.delattr(os, "fork")
    assert built_apart(lambda: box, 10.0) is box


def test_a_build_that_crashes_or_hangs_is_a_failed_build_and_this_process_goes_on():
    def crash():
        os.kill(os.getpid(), signal.SIGSEGV)

    assert built_apart(crash, 10.0) is None
    start = time.monotonic()
    assert built_apart(lambda: time.sleep(30), 0.5) is None
    assert time.monotonic() - start < 5
