#!/bin/bash
# The progress line of the long commands (map, tolerance, pareto, robust
# optimize, sweep and simulate; report's --help): on a terminal
# (a pseudo-terminal from util-linux `script`) stderr shows "usm CMD:
# DONE/TOTAL UNIT" lines rewritten with \r, the last one erased; with stderr
# redirected to a file, or with --quiet, stderr stays empty; stdout is the
# same bytes in every case.
#
# usage: progress_cli.sh PATH/TO/usm
set -u
USM=${1:?usage: progress_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

if ! command -v script >/dev/null || ! script -qec true /dev/null >/dev/null 2>&1; then
    echo "SKIP: no util-linux script or no pseudo-terminal"
    exit 77
fi

# on a pseudo-terminal: stdout to $1, the terminal's bytes to $2
on_tty() {
    local o=$1 tty=$2
    shift 2
    local cmd="'$USM'"
    for a in "$@"; do cmd+=" '$a'"; done
    timeout 120 script -qec "$cmd >'$o'" /dev/null >"$tty" 2>&1
}

# the same stdout but for the wall-clock "seconds" or "wall_time" of a --json object
same_out() {
    cmp -s <(grep -vE '"(seconds|wall_time)"' "$1") <(grep -vE '"(seconds|wall_time)"' "$2")
}

check_cmd() {
    local name=$1 total=$2 unit=$3
    shift 3
    checks=$((checks + 1))
    run "$@"
    local rc=$?
    cp "$out" "$tmp/piped.out"
    if [ $rc -ne 0 ]; then fail "usm $*: exit $rc"; return; fi
    if [ -s "$err" ]; then fail "usm $* 2>file: stderr not empty"; return; fi

    checks=$((checks + 1))
    on_tty "$tmp/tty.out" "$tmp/tty" "$@" || { fail "usm $* on a terminal: exit $?"; return; }
    tr '\r' '\n' <"$tmp/tty" >"$tmp/tty.lines"
    if ! grep -qE "^usm $name: [0-9]+/$total $unit \([0-9]+%\)" "$tmp/tty.lines"; then
        fail "usm $* on a terminal: no 'usm $name: N/$total $unit' line: $(head -c 300 "$tmp/tty.lines")"
        return
    fi
    if ! grep -qE "^usm $name: ($total)/\1 $unit \(100%\)" "$tmp/tty.lines"; then
        fail "usm $* on a terminal: the line never reached its total"; return
    fi
    # erased at the end: the terminal's last bytes are blanks and a \r
    if [ -n "$(tail -n 1 "$tmp/tty.lines" | tr -d ' ')" ] || [ "$(tail -c 1 "$tmp/tty" | od -An -c | tr -d ' ')" != '\r' ]; then
        fail "usm $* on a terminal: the progress line is not erased at the end"; return
    fi
    if ! same_out "$tmp/piped.out" "$tmp/tty.out"; then
        fail "usm $*: stdout differs on a terminal"; return
    fi

    checks=$((checks + 1))
    on_tty "$tmp/quiet.out" "$tmp/quiet" "$@" --quiet || { fail "usm $* --quiet: exit $?"; return; }
    if [ -s "$tmp/quiet" ]; then
        fail "usm $* --quiet on a terminal: $(head -c 200 "$tmp/quiet" | od -c | head -3)"; return
    fi
    if ! same_out "$tmp/piped.out" "$tmp/quiet.out"; then fail "usm $* --quiet: stdout differs"; fi
}

# about a second of samples: lines between the first and the last
check_cmd tolerance 20000 samples tolerance --samples 20000 --vary F0=normal:5% --threads 2
check_cmd map 96 points map --x-points 12 --y-points 8 --threads 2
check_cmd pareto 6 'front points' pareto --objectives speed,efficiency --vary F0=0.3:0.6 --points 6
# robust design: the designs against the searches' budgets (a total that may grow)
check_cmd optimize '[0-9]+' designs optimize --objective efficiency --vary f=34000:42000 \
    --vary F0=0.2:1.0 --constraint 'speed>=6' --constraint 'yield>=0.99' \
    --scatter c_r=normal:2% --scatter f=normal:1% --samples 600 --verify-samples 1200 \
    --max-evals 6 --starts 1 --json

# sweep and simulate (their stderr may carry warnings): the same line on a
# terminal, none with --quiet or on a redirected stderr, the same stdout
for spec in "sweep|40|points|sweep --over T --from 0 --to 0.005 --points 40" \
            "simulate|740|periods|simulate --duration 0.02 --rate 0 --json"; do
    IFS='|' read -r name total unit cmd <<<"$spec"
    checks=$((checks + 1))
    # shellcheck disable=SC2086
    run $cmd
    cp "$out" "$tmp/piped.out"
    [ -s "$err" ] && grep -qv warning "$err" && { fail "usm $cmd 2>file: stderr: $(head -c 200 "$err")"; continue; }
    # shellcheck disable=SC2086
    on_tty "$tmp/tty.out" "$tmp/tty" $cmd || { fail "usm $cmd on a terminal: exit $?"; continue; }
    tr '\r' '\n' <"$tmp/tty" >"$tmp/tty.lines"
    grep -qE "^usm $name: $total/$total $unit \(100%\)" "$tmp/tty.lines" ||
        fail "usm $cmd on a terminal: no 'usm $name: $total/$total $unit' line: $(head -c 300 "$tmp/tty.lines")"
    same_out "$tmp/piped.out" "$tmp/tty.out" || fail "usm $cmd: stdout differs on a terminal"
    # --quiet: no progress line on a terminal (a warning may stand there)
    checks=$((checks + 1))
    # shellcheck disable=SC2086
    on_tty "$tmp/quiet.out" "$tmp/quiet" $cmd --quiet || { fail "usm $cmd --quiet: exit $?"; continue; }
    ! tr '\r' '\n' <"$tmp/quiet" | grep -q "^usm $name: [0-9]" ||
        fail "usm $cmd --quiet on a terminal: a progress line"
    same_out "$tmp/piped.out" "$tmp/quiet.out" || fail "usm $cmd --quiet: stdout differs"
done

# --help names --quiet
for c in map tolerance report pareto optimize sweep simulate; do
    checks=$((checks + 1))
    run $c --help
    grep -q -- '--quiet' "$out" || fail "usm $c --help does not name --quiet"
done

finish progress_cli
