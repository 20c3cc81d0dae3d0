#!/bin/bash
# Floquet failures from the command line ("Messages"):
#  - where the variational integration (CVODES) fails, `usm` exits 1 with
#    exactly one stderr line "usm: floquet: ..." naming CVODES' reason, and
#    nothing of CVODES' own printing; so does the Magnus method where its
#    series diverges;
#  - the default method (auto) answers there (falling back to the product of
#    exponentials), and a sweep through such parameters prints at most one
#    stderr line;
#  - run in the sanitizer build (ctest with ASAN_OPTIONS=detect_leaks=1, see
#    tests/run-all), LeakSanitizer makes any leak on these paths (CVODES'
#    malloc'ed flag names) an abort, which fails the checks below.
#
# usage: floquet_failures_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: floquet_failures_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# expect_fail REGEX ARGS...: exit 1, one line "usm: ..." matching REGEX, no stdout.
expect_fail() {
    local regex=$1
    shift
    checks=$((checks + 1))
    run "$@"
    local rc=$?
    if [ $rc -ne 1 ]; then fail "usm $*: exit $rc, want 1"; return; fi
    if [ "$(wc -l <"$err")" -ne 1 ]; then fail "usm $*: stderr is not one line"; return; fi
    if ! grep -qE -- "^usm: $regex" "$err"; then fail "usm $*: stderr does not match '$regex'"; return; fi
    if grep -q 'CVODES ERROR' "$err"; then fail "usm $*: CVODES printed"; return; fi
    if [ -s "$out" ]; then fail "usm $*: output on stdout"; return; fi
}

# Stiff linearisations: Adams with fixed-point iteration gives up (CV_TOO_MUCH_WORK).
# (usm steady computes every root's multipliers: the message names the root)
cvodes="floquet: root #1 \\(theta = [^)]*\\): CVODES failed at t = .*CV_TOO_MUCH_WORK"
# (each takes CVODES' 200000 steps to give up: a few, to keep the test short)
expect_fail "$cvodes" steady --set d_R=1e12 --floquet-method variational
expect_fail "$cvodes" steady --model 4dof --set d_R=1e8 --json --floquet-method=variational
# magnus carries the stiff mode in its exact flows: it answers there too
if expect_rc 0 steady --set d_R=1e12 --floquet-method magnus --json; then
    py "f = o['floquet']; assert 0.999 < f['max_modulus'] < 1 and f['stable'], f"
fi

# the default answers: the multiplier of the axial rotor mode tends to 1 from below
if expect_rc 0 steady --set d_R=1e12 --json; then
    py "f = o['floquet']; assert 0.999 < f['max_modulus'] < 1 and f['stable'], f"
fi

# A sweep into the stiff range: exit 0 with the failed points marked, or exit 1;
# either way at most one stderr line and none of CVODES' printing.
checks=$((checks + 1))
run sweep --over d_R --from 1 --to 1e12 --points 3
rc=$?
if [ $rc -ne 0 ] && [ $rc -ne 1 ]; then
    fail "usm sweep --over d_R: exit $rc"
elif [ "$(wc -l <"$err")" -gt 1 ] || { [ $rc -eq 1 ] && [ "$(wc -l <"$err")" -ne 1 ]; }; then
    fail "usm sweep --over d_R: $(wc -l <"$err") stderr lines"
elif grep -q 'CVODES ERROR' "$err"; then
    fail "usm sweep --over d_R: CVODES printed"
fi

finish floquet_failures
