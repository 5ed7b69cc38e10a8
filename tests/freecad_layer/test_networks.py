# SPDX-License-Identifier: LGPL-2.1-or-later
"""The workbench's networks load once, in the background, and whoever needs them waits
for that load (freecad_layer/networks.py; the GUI side: tests/freecad/test_responsiveness.py)."""

import threading

import pytest

from Sketch2CADWorkbench.freecad_layer import networks


@pytest.fixture
def fresh(monkeypatch):
    """networks with nothing loaded, and a stand-in load that waits for `gate` and fails
    as many times as `failures` says."""
    for name, value in (
        ("_thread", None),
        ("_predictor", None),
        ("_error", None),
        ("_seconds", None),
    ):
        monkeypatch.setattr(networks, name, value)
    gate, calls, failures = threading.Event(), [], []

    def load():
        calls.append(threading.current_thread().name)
        assert gate.wait(30)
        if failures:
            failures.pop()
            raise FileNotFoundError("no network weights at nowhere.pt")
        return object()

    monkeypatch.setattr(networks, "_load", load)
    yield gate, calls, failures
    gate.set()
    if networks._thread is not None:
        networks._thread.join(30)


def test_the_load_starts_once_in_a_background_thread(fresh):
    gate, calls, _ = fresh
    assert networks.start_loading()
    assert not networks.start_loading()  # a second activation while loading
    assert networks.loading()
    gate.set()
    networks._thread.join(30)
    assert not networks.loading()
    assert not networks.start_loading()  # loaded: nothing to start
    assert calls == ["Sketch2CAD networks"]


def test_predictor_waits_for_the_background_load_instead_of_loading_again(fresh):
    gate, calls, _ = fresh
    networks.start_loading()
    threading.Timer(0.2, gate.set).start()
    p = networks.predictor()  # blocks until the thread is done
    assert p is networks.predictor() and len(calls) == 1


def test_without_a_background_load_predictor_loads_in_the_calling_thread(fresh):
    gate, calls, _ = fresh
    gate.set()
    p = networks.predictor()
    assert p is networks.predictor()
    assert calls == [threading.current_thread().name]


def test_a_failed_background_load_is_retried_and_its_error_raised_where_it_is_needed(fresh):
    gate, calls, failures = fresh
    failures += [1, 1]  # the background load and the first retry fail
    networks.start_loading()
    gate.set()
    networks._thread.join(30)
    assert networks._error == "FileNotFoundError: no network weights at nowhere.pt"
    with pytest.raises(FileNotFoundError, match="no network weights"):
        networks.predictor()
    assert networks.predictor() is not None  # the weights are back: loaded now
    assert len(calls) == 3
