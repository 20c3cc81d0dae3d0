#!/bin/bash
# `usm simulate` and the paper's twist law: a run it would slow down
# for minutes is refused at once with one line naming the remedy; a shorter run
# that slows down warns (before it starts on a terminal, else in its one stop line or after it); twist_integrated runs silently.
#
# usage: simulate_twist_cli.sh PATH/TO/usm
set -u

USM=${1:?usage: simulate_twist_cli.sh PATH/TO/usm}
. "$(dirname "$0")/../cli_common.sh"

# refused: exit 2, one line naming --duration's field and twist_integrated
expect_bad "duration" "twist_integrated" simulate --model 4dof --duration 10 --rate 0
expect_bad "--max-twist-growth" "must be >= 0" simulate --model 4dof --duration 1 --max-twist-growth -1

# warned: before the run on a terminal; here (no terminal) in the one line of
# a run stopped early by the step cap
if expect_rc 1 simulate --model 4dof --duration 0.3 --rate 0 --max-steps 10; then
    [ "$(wc -l <"$err")" -eq 1 ] || fail "exit 1 printed $(wc -l <"$err") stderr lines, want 1"
    grep -q '^usm: stopped at .*warning: .*twist_integrated' "$err" || fail "no warning in the stop line"
fi
# the limit lifted: runs (stopped by the step cap), with the warning in the JSON
if expect_rc 1 simulate --model 4dof --duration 10 --rate 0 --max-steps 10 --max-twist-growth 0 --json; then
    py "assert o['twist_growth'] > 400 and 'twist_integrated' in o['warning'], o.get('warning')"
fi
# twist_integrated: neither
if expect_rc 1 simulate --model 4dof --variant twist_integrated --duration 10 --rate 0 --max-steps 10 --json; then
    grep -q 'warning' "$err" && fail "twist_integrated warned"
    py "assert o['twist_growth'] == 0 and 'warning' not in o"
fi

finish simulate_twist_cli
