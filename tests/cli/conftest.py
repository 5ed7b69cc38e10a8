# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the command-line tests share."""

import io
import sys

import pytest


class Terminal(io.StringIO):
    """A stream that says it is a terminal and keeps what is written to it."""

    def isatty(self):
        return True


@pytest.fixture
def stderr_of(monkeypatch):
    """stderr_of(terminal): sys.stderr replaced by a stream kept in memory, a terminal or
    not; returns it."""

    def replace(terminal: bool) -> io.StringIO:
        stream = Terminal() if terminal else io.StringIO()
        monkeypatch.setattr(sys, "stderr", stream)
        return stream

    return replace
