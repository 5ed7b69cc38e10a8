#!/usr/bin/env bash
# The README's test command (make test): ruff (lint and format) over the repository and mypy
# over the core (pyproject.toml says which), then the whole suite on the host's FreeCAD
# 0.20.2, then the FreeCAD tests (tests/freecad: document, GUI, STEP, FCStd reopening, a session
# interpreted inside FreeCAD) on FreeCAD 1.0 and 1.1.3 in their Debian chroots
# (scripts/chroot.sh builds each the first time and reuses it after). With arguments, only
# `pytest ARGS` here, on this machine's FreeCAD. pytest's exit 5 (no tests) is a failure.
set -uo pipefail
cd "$(dirname "$0")/.."
export LANG=C.UTF-8

pytest_here() {
    .bin/python -m pytest -q "$@"
    local rc=$?
    if [ $rc -eq 5 ]; then
        echo "run_tests: pytest collected no tests; failing" >&2
        return 1
    fi
    return $rc
}

if [ $# -gt 0 ]; then
    pytest_here "$@"
    exit $?
fi

summary=()
passed=0
failed=0
rc=0
count() {  # count CLOSING-LINE WORDS: the sum of the numbers before WORDS
    echo "$1" | grep -oE "[0-9]+ $2" | awk '{s += $1} END {print s + 0}'
}
run() {  # run LABEL COMMAND...: one pytest run, its closing line kept for the summary
    local label=$1 log
    shift
    log=$(mktemp)
    "$@" 2>&1 | tee "$log"
    local code=${PIPESTATUS[0]}
    local closing
    closing=$(grep -E '^=*\s*[0-9]+ (passed|failed)|^[0-9]+ (passed|failed)' "$log" | tail -n 1 | sed 's/=//g; s/^ *//')
    summary+=("$label: ${closing:-no pytest summary (exit $code)}")
    passed=$((passed + $(count "$closing" 'passed')))
    failed=$((failed + $(count "$closing" '(failed|errors?)')))
    [ -n "$closing" ] || failed=$((failed + 1))
    [ "$code" -eq 0 ] || rc=1
    rm -f "$log"
}

check() {  # check LABEL COMMAND...: a linter; its failure fails the run
    local label=$1
    shift
    if "$@"; then
        summary+=("$label: clean")
    else
        summary+=("$label: FAILED")
        failed=$((failed + 1))
        rc=1
    fi
}

check "ruff check" .bin/python -m ruff check .
check "ruff format --check" .bin/python -m ruff format --check .
check "mypy (the core)" .bin/python -m mypy
run "FreeCAD 0.20.2 (host), whole suite" pytest_here
for suite in trixie forky; do
    run "FreeCAD $( [ $suite = trixie ] && echo 1.0 || echo 1.1.3 ) ($suite chroot), tests/freecad" \
        bash scripts/chroot.sh "$suite" "bash scripts/run_tests.sh tests/freecad"
done

echo
printf 'run_tests: %s\n' "${summary[@]}"
echo "$passed passed, $failed failed"
exit $rc
