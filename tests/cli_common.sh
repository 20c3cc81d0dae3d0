# Shared by the command-line test scripts: sourced after USM is set.
#   run ARGS...            usm with a time limit (a hang is a failure, not a wait)
#   fail MESSAGE           count a failure, show stdout and stderr
#   expect_bad FIELD REASON ARGS...   exit 2, one line "usm: ..." naming FIELD and REASON
#   expect_rc RC ARGS...   exit status RC and no NaN/inf on stdout
#   py CODE                Python asserts on the JSON in stdout (as `o`)
#   py_file FILE CODE      the same on the JSON in FILE
#   finish NAME            print the counts; the status is 0 when nothing failed
PY=/usr/bin/python3
failures=0
checks=0

tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
out=$tmp/stdout
err=$tmp/stderr

fail() {
    failures=$((failures + 1))
    echo "FAIL: $*"
    echo "  stdout: $(head -c 600 "$out")"
    echo "  stderr: $(head -c 600 "$err")"
}

run() {
    timeout "${USM_RUN_TIMEOUT:-60}" "$USM" "$@" >"$out" 2>"$err"
}

no_nan() {
    ! grep -qiwE 'nan|[+-]?inf(inity)?' "$out"
}

expect_bad() {
    local field=$1 reason=$2
    shift 2
    checks=$((checks + 1))
    run "$@"
    local rc=$?
    if [ $rc -ne 2 ]; then fail "usm $*: exit $rc, want 2"; return; fi
    if [ "$(wc -l <"$err")" -ne 1 ]; then fail "usm $*: stderr is not one line"; return; fi
    if ! grep -q '^usm: ' "$err"; then fail "usm $*: stderr lacks the 'usm: ' prefix"; return; fi
    if ! grep -qF -- "$field" "$err"; then fail "usm $*: stderr does not name '$field'"; return; fi
    if ! grep -qiE -- "$reason" "$err"; then fail "usm $*: stderr does not say '$reason'"; return; fi
    if [ -s "$out" ] || ! no_nan; then fail "usm $*: output on stdout"; return; fi
}

expect_rc() {
    local want=$1
    shift
    checks=$((checks + 1))
    run "$@"
    local rc=$?
    if [ $rc -ne "$want" ]; then fail "usm $*: exit $rc, want $want"; return 1; fi
    if ! no_nan; then fail "usm $*: NaN or inf on stdout"; return 1; fi
    return 0
}

py_file() {
    checks=$((checks + 1))
    if ! "$PY" -c "import json,sys
o = json.load(open(sys.argv[1]))
$2" "$1" 2>"$tmp/py"; then
        failures=$((failures + 1))
        echo "FAIL: JSON check: $(tail -n 1 "$tmp/py")"
    fi
    return 0
}

py() {
    py_file "$out" "$1"
}

finish() {
    echo "$1: $checks checks, $failures failures"
    [ "$failures" -eq 0 ]
}
