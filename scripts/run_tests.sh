#!/usr/bin/env bash
# Runs the whole suite. pytest's exit 5 (no tests collected) is a failure, not a pass.
set -uo pipefail
cd "$(dirname "$0")/.."
export LANG=C.UTF-8
.bin/python -m pytest -q "$@"
rc=$?
if [ $rc -eq 5 ]; then
    echo "run_tests: pytest collected no tests; failing" >&2
    exit 1
fi
exit $rc
