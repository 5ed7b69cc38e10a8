# SPDX-License-Identifier: LGPL-2.1-or-later
"""Small seeded fuzzing campaigns (the full ones: tests/fuzz/run.py): every malformed
protocol or session is a clean error or valid; no stroke set crashes, changes the model
or yields an invalid solid; killed and concurrent writers never leave a broken file;
an output lands where its path leads, leaving links, devices and FIFOs what they are;
geometry that is not what it says is refused. Each prints its counts (pytest -s)."""

import fuzzing


def _no_failures(tally, name=""):
    print(tally.line(name))
    bad = {
        k: tally.counts[k]
        for k in ("crash", "invalid", "changed", "broken", "leftover")
        if tally.counts[k]
    }
    assert not bad, (bad, tally.crashes)


def test_malformed_protocols_are_clean_errors():
    t = fuzzing.malformed_protocols(120, seed=11)
    _no_failures(t, "malformed protocols")
    assert t.counts["clean"] > 60  # the mutations do reach the checks


def test_malformed_sessions_are_clean_errors():
    t = fuzzing.malformed_sessions(120, seed=12)
    _no_failures(t, "malformed sessions")
    assert t.counts["clean"] > 60


def test_random_strokes_never_crash_or_change_the_model():
    _no_failures(fuzzing.random_strokes(12, seed=13), "random strokes")


def test_killed_writers_leave_the_whole_file_and_no_temporary():
    t = fuzzing.killed_writers(4, seed=14)
    _no_failures(t, "killed writers")
    assert t.counts["accepted"] == 4


def test_concurrent_writers_never_show_a_reader_a_partial_file():
    t = fuzzing.concurrent_writers(4.0)
    _no_failures(t, "concurrent writers")
    assert t.counts["accepted"] > 10


def test_outputs_land_where_their_path_leads_and_keep_its_kind():
    t = fuzzing.output_targets(seed=15)
    _no_failures(t, "output targets")
    assert t.counts["accepted"] >= 5 and t.counts["clean"] >= 2  # folder, under a file


def test_geometry_that_is_not_what_it_says_is_refused():
    t = fuzzing.hostile_geometry(6, seed=16)
    _no_failures(t, "hostile geometry")
    assert t.counts["clean"] == 6
