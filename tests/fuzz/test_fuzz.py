# SPDX-License-Identifier: LGPL-2.1-or-later
"""Small seeded fuzzing campaigns (the full ones: tests/fuzz/run.py): every malformed
protocol or session is a clean error or valid; no stroke set crashes, changes the model
or yields an invalid solid; killed and concurrent writers never leave a broken file."""

import fuzzing


def _no_failures(tally):
    bad = {
        k: tally.counts[k]
        for k in ("crash", "invalid", "changed", "broken", "leftover")
        if tally.counts[k]
    }
    assert not bad, (bad, tally.crashes)


def test_malformed_protocols_are_clean_errors():
    t = fuzzing.malformed_protocols(120, seed=11)
    _no_failures(t)
    assert t.counts["clean"] > 60  # the mutations do reach the checks


def test_malformed_sessions_are_clean_errors():
    t = fuzzing.malformed_sessions(120, seed=12)
    _no_failures(t)
    assert t.counts["clean"] > 60


def test_random_strokes_never_crash_or_change_the_model():
    _no_failures(fuzzing.random_strokes(12, seed=13))


def test_killed_writers_leave_the_whole_file_and_no_temporary():
    t = fuzzing.killed_writers(4, seed=14)
    _no_failures(t)
    assert t.counts["accepted"] == 4


def test_concurrent_writers_never_show_a_reader_a_partial_file():
    t = fuzzing.concurrent_writers(4.0)
    _no_failures(t)
    assert t.counts["accepted"] > 10
