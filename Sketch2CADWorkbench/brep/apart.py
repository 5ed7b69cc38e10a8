# SPDX-License-Identifier: LGPL-2.1-or-later
"""OCCT builds that may crash or loop, run apart from the process that asks for them.

    built_apart(build, timeout_s) -> cq.Shape | None

Some OCCT algorithms end the whole process on some inputs (a thick solid's offset on
sampled models of planes and cones; a fillet around a face's outline of lines and arcs)
or never return. In FreeCAD that process holds the user's unsaved document, so where
the system can fork, such a build runs in a child process that hands the shape back as
BREP text; a crash or a timeout is then a failed build, as OCCT's own "not done" is.
Elsewhere (Windows) the build runs in this process.
"""

from __future__ import annotations

import faulthandler
import io
import os
import select
import signal
import time
from collections.abc import Callable

import cadquery as cq


def built_apart(build: Callable[[], cq.Shape | None], timeout_s: float) -> cq.Shape | None:
    """`build()`'s shape, built in a child process where the system can fork; None where
    it returns None, crashes the child, or runs past `timeout_s`."""
    if not hasattr(os, "fork"):
        return build()
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: build, send the BREP (nothing when it fails), leave at once
        try:
            faulthandler.disable()  # a crash here is a failed build, not a report to print
            os.close(read)
            got = build()
            if got is not None:
                buffer = io.BytesIO()
                got.exportBrep(buffer)
                os.write(write, buffer.getvalue())
        finally:
            os._exit(0)
    os.close(write)
    data, deadline = bytearray(), time.monotonic() + timeout_s
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([read], [], [], left)[0]:
                os.kill(pid, signal.SIGKILL)
                return None
            chunk = os.read(read, 1 << 20)
            if not chunk:
                break
            data += chunk
    finally:
        os.close(read)
        os.waitpid(pid, 0)
    return cq.Shape.importBrep(io.BytesIO(bytes(data))) if data else None
