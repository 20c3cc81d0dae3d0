#!/bin/bash
# Outputs whole or absent: every single-file output of the command
# (map --out, simulate --out, periodic --orbit, the --plot files, the
# tolerance checkpoint and --out files) is written to a temporary beside it
# and renamed into place only when whole; nothing is written through a
# symlink (without --force a symlink is refused, with --force it is replaced,
# its target untouched); an output that cannot be written fails at once (exit
# 2, one line naming the option) before any computation; a killed run leaves
# no file under the final name and nothing that blocks the re-run.  Also the
# hostile inputs of the same issue: ranges that overflow, periodic without a
# solution (exit 3), corrupted checkpoints.
#
# usage: output_files_cli.sh PATH/TO/usm
set -u
USM=${1:?usage: output_files_cli.sh PATH/TO/usm}
# a hang guard, not a speed check: its --quick reports take over 60 s under ASan
# on a loaded 2-core machine
USM_RUN_TIMEOUT=600
. "$(dirname "$0")/../cli_common.sh"

d=$tmp/w
mkdir "$d"
echo precious >"$d/precious"
untouched() { [ "$(cat "$d/precious")" = precious ] || fail "$1: the symlink's target was written"; }
no_temp() { ! ls -A "$d" | grep -q '\.part$' || fail "$1: a temporary was left: $(ls -A "$d" | grep '\.part$')"; }

M="map --x-points 3 --y-points 2"

# ---- map --out ------------------------------------------------------------------
ln -s precious "$d/link.csv"
ln -s nowhere "$d/dangling.csv"
expect_bad "--out" "symbolic link" $M --out "$d/link.csv"
untouched "map --out link"
expect_bad "--out" "symbolic link" $M --out "$d/dangling.csv"
[ -e "$d/nowhere" ] && fail "map --out: created the dangling symlink's target"
expect_bad "--out" "No such file or directory" $M --out "$d/nodir/m.csv"
expect_bad "--out" "is a directory" $M --out "$d"
if expect_rc 0 $M --out "$d/link.csv" --force; then
    untouched "map --out link --force"
    [ -f "$d/link.csv" ] && [ ! -L "$d/link.csv" ] || fail "map --force: the symlink was not replaced by the file"
    head -n 1 "$d/link.csv" | grep -q '^f \[Hz\],T \[N m\],' || fail "map --force: the file is not the map"
fi
expect_rc 0 $M --out "$d/m.csv" && { [ "$(wc -l <"$d/m.csv")" -eq 7 ] || fail "map --out: not whole"; }
expect_bad "--out" "exists" $M --out "$d/m.csv"
no_temp "map"

# ---- simulate --out: a killed run leaves no file under the final name ------------
ln -s precious "$d/slink.csv"
expect_bad "--out" "symbolic link" simulate --duration 1e-4 --out "$d/slink.csv"
untouched "simulate --out link"
expect_bad "--out" "No such file or directory" simulate --duration 1e-4 --out "$d/nodir/s.csv"
checks=$((checks + 1))
"$USM" simulate --duration 1 --out "$d/killed.csv" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 50); do ls -A "$d" | grep -q '^\.killed\.csv\..*\.part$' && break; sleep 0.05; done
sleep 0.2
kill -9 $pid 2>/dev/null
wait $pid 2>/dev/null
[ -e "$d/killed.csv" ] && fail "simulate killed: a partial file under the final name"
ls -A "$d" | grep -q '^\.killed\.csv\..*\.part$' || fail "simulate killed: no temporary (was it killed while writing?)"
if expect_rc 0 simulate --duration 1e-4 --out "$d/killed.csv"; then
    [ -s "$d/killed.csv" ] || fail "simulate re-run: no file"
    no_temp "simulate re-run (the killed run's temporary removed)"
fi

# ---- periodic --orbit, and no solution is exit 3 like steady ---------------------
P="periodic --variant imperfect --set phase_error=0.05"
expect_bad "--orbit" "No such file or directory" $P --orbit "$d/nodir/o.csv"
ln -s precious "$d/olink.csv"
expect_bad "--orbit" "symbolic link" $P --orbit "$d/olink.csv"
untouched "periodic --orbit link"
if expect_rc 0 $P --orbit "$d/olink.csv" --force; then
    untouched "periodic --orbit link --force"
    [ ! -L "$d/olink.csv" ] && [ "$(wc -l <"$d/olink.csv")" -gt 100 ] || fail "periodic --orbit --force"
fi
expect_rc 3 periodic --variant imperfect --set m0=1e-9 &&
    { [ "$(wc -l <"$err")" -eq 1 ] && grep -q 'no stationary solution' "$err" || fail "periodic m0=1e-9: stderr"; }
expect_rc 3 steady --set m0=1e-9
expect_rc 3 periodic --variant imperfect --set m0=1e-9 --json && py 'assert o["converged"] is False and o["error"]'

# ---- --plot data files ----------------------------------------------------------
S="sweep --over T --from 0 --to 0.002 --points 3"
ln -s precious "$d/pl.csv"
expect_bad "--plot" "symbolic link" $S --plot "$d/pl"
ln -s nowhere "$d/pg.gp"
expect_bad "--plot" "symbolic link" $M --plot "$d/pg"
expect_bad "--plot" "No such file or directory" $S --plot "$d/nodir/p"
untouched "sweep --plot link"
rm -f "$d/pl.csv" "$d/pg.gp"
# gnuplot's log is an output too: a user's PREFIX.log is refused before the sweep
echo "my log" >"$d/pq.log"
expect_bad "--plot" "exists" $S --plot "$d/pq"
checks=$((checks + 1))
[ "$(cat "$d/pq.log")" = "my log" ] || fail "--plot: a user's PREFIX.log was changed"
rm -f "$d/pq.log"

# ---- tolerance --checkpoint -----------------------------------------------------
T="tolerance --samples 40 --vary F0=normal:10%"
ln -s precious "$d/ck.tmp"
expect_rc 0 $T --checkpoint "$d/ck" --json && untouched "checkpoint beside ck.tmp -> precious"
[ -L "$d/ck.tmp" ] || fail "checkpoint: ck.tmp replaced"
head -c 26 "$d/ck" | grep -q 'usm tolerance checkpoint' || fail "checkpoint not written"
expect_bad "--checkpoint" "No such file or directory" $T --checkpoint "$d/nodir/ck"
ln -s nowhere "$d/ckdangling"
expect_bad "--checkpoint" "symbolic link" $T --checkpoint "$d/ckdangling"
expect_bad "--checkpoint" "not a usm tolerance checkpoint" $T --checkpoint "$d"
no_temp "checkpoint"

# two runs sharing a checkpoint: the second fails at once (flock on .ck.usm-lock)
L="tolerance --samples 40000 --vary F0=normal:10% --threads 1"
"$USM" $L --checkpoint "$d/shared.ck" >/dev/null 2>&1 &
first=$!
for _ in $(seq 100); do [ -e "$d/.shared.ck.usm-lock" ] && break; sleep 0.05; done
expect_bad "--checkpoint $d/shared.ck" "another run is using it" $L --checkpoint "$d/shared.ck"
kill $first 2>/dev/null
wait $first 2>/dev/null

# ---- tolerance --out DIR ----------------------------------------------------------
ln -s nowhere "$d/tdangling"
expect_bad "--out" "symbolic link" $T --out "$d/tdangling"
expect_bad "--out" "No such file or directory" $T --out "$d/nodir/t"
echo x >"$d/afile"
expect_bad "--out" "not a directory" $T --out "$d/afile"
# an empty directory (what a run killed before writing leaves) is taken without --force
mkdir "$d/empty"
expect_rc 0 $T --out "$d/empty" && { [ -s "$d/empty/samples.csv" ] || fail "tolerance --out empty DIR"; }
expect_bad "--out" "exists" $T --out "$d/empty"
# DIR appears whole: written in a stage beside it, renamed when samples.csv and summary.md are
# there; a run killed leaves no DIR (its stage is removed by the next run)
checks=$((checks + 1))
"$USM" $L --out "$d/tk" >/dev/null 2>&1 &
first=$!
sleep 0.5
kill -9 $first 2>/dev/null
wait $first 2>/dev/null
if [ -e "$d/tk" ]; then
    [ "$(wc -l <"$d/tk/samples.csv")" -eq 40001 ] && [ -s "$d/tk/summary.md" ] ||
        fail "tolerance --out killed: a partial DIR"
else
    expect_rc 0 $T --out "$d/tk" && { [ -s "$d/tk/summary.md" ] || fail "tolerance --out re-run"; }
fi
checks=$((checks + 1))
! ls -A "$d" | grep -q '^\.tk\.usm-new-' || fail "tolerance --out: a stage left: $(ls -A "$d" | grep usm-new)"

# ---- a symlink planted in a report directory: replaced, its target untouched ---------
r=$d/report
if expect_rc 0 report --out "$r" --quick --no-plots; then
    ln -sf ../precious "$r/fig09_speed_frequency_3dof.csv"
    ln -sf ../precious "$r/report.html"
    if expect_rc 0 report --out "$r" --quick --no-plots; then
        untouched "report into a directory with planted symlinks"
        [ ! -L "$r/fig09_speed_frequency_3dof.csv" ] && [ ! -L "$r/report.html" ] ||
            fail "report: the planted symlinks are still there"
        ! ls -A "$r" | grep -q '\.part$' || fail "report: temporaries left"
    fi
fi

# ---- ranges: finite, and their width representable (it used to hang) --------------
expect_bad "from, to" "overflows" sweep --periodic --variant imperfect --over phase_error --from -1e308 --to 1e308 --points 3
expect_bad "from, to" "overflows" sweep --over T --from -1e308 --to 1e308 --points 3
expect_bad "--x-from" "overflows" map --x f --x-from -1e308 --x-to 1e308
expect_bad "--y-from" "overflows" map --y-from -1.7e308 --y-to 1.7e308
expect_bad "--vary T" "overflows" tolerance --samples 3 --vary T=uniform:-1e308:1e308

# ---- a checkpoint's data validated on load -----------------------------------------
# corrupt SRC DST SAMPLE COLUMN VALUE [keep-hash]: one double of a row changed (columns: F0,
# theta, rotor_speed, F_n, F_t, max_modulus, efficiency, stable, stick_admissible, exists,
# operating_point, op_class, validity, good, redraws), the CRC-32 (zlib's, of every byte after
# the first line; format 3) recomputed (so that the row check itself is tested) unless
# keep-hash
corrupt() {
    "$PY" - "$@" <<'PYEOF'
import struct, sys, zlib
src, dst, sample, col, value = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
rehash = len(sys.argv) < 7
data = bytearray(open(src, "rb").read())
start = data.index(b"\nend\n") + 5 + 8           # after ORDER
width, block = 15, 64
n = struct.unpack_from("<Q", data, start)[0]
assert n == 1
off = start + 8 + 8 + (sample * width + col) * 8  # count, block index, the rows
struct.pack_into("<d", data, off, value)
if rehash:
    end = len(data) - 16
    struct.pack_into("<Q", data, end, zlib.crc32(bytes(data[data.index(b"\n") + 1:end])))
open(dst, "wb").write(data)
PYEOF
}
T="tolerance --samples 40 --vary F0=normal:10% --spec rotor_speed<=-5"
if expect_rc 0 $T --checkpoint "$d/good.ck" --json; then
    cp "$out" "$d/fresh.json"
    # without the "timings" line (wall seconds, different in every run)
    expect_rc 0 $T --checkpoint "$d/good.ck" --json &&
        { cmp -s <(grep -v '^  "timings": ' "$out") <(grep -v '^  "timings": ' "$d/fresh.json") ||
          fail "resume differs"; }
    bad_ck() { # NAME REASON SAMPLE COLUMN VALUE [keep-hash]
        local name=$1 reason=$2
        shift 2
        corrupt "$d/good.ck" "$d/$name.ck" "$@" || { fail "corrupt $name"; return; }
        cp "$d/$name.ck" "$d/$name.orig"
        expect_bad "--checkpoint $d/$name.ck" "$reason" $T --checkpoint "$d/$name.ck" --json
        cmp -s "$d/$name.ck" "$d/$name.orig" || fail "checkpoint $name: the refused file was changed"
    }
    bad_ck nan_redraws 'sample 3: redraws nan' 3 14 nan
    bad_ck big_redraws 'sample 3: redraws 1e\+300' 3 14 1e300
    bad_ck neg_redraws 'sample 0: redraws -1' 0 14 -1
    bad_ck frac_redraws 'redraws 0.5' 5 14 0.5
    bad_ck huge_redraws 'redraws 9.22337e\+18' 5 14 9223372036854775808
    bad_ck good_no_exists 'sample 7: exists 2' 7 9 2
    bad_ck good_flag 'good is 0 but' 7 13 0
    bad_ck nan_param 'sample 2: F0 = nan' 2 0 nan
    bad_ck neg_param 'sample 2: not physical' 2 0 -1
    bad_ck inf_theta 'sample 4: theta = inf' 4 1 inf
    bad_ck stable_flag 'sample 4: stable = 0' 4 7 0
    bad_ck stick_flag 'sample 4: stick_admissible = 0.5' 4 8 0.5
    bad_ck op_index 'sample 4: operating_point = -1' 4 10 -1
    bad_ck op_class 'sample 4: op_class = 9' 4 11 9
    # the validity and the stick flag as the row's own F_n, F_t and mu0 imply (sample 4 is
    # valid: mu0 F_n > |F_t|)
    bad_ck validity 'sample 4: validity = 2 where its F_n, F_t and mu0 say 0' 4 12 2
    bad_ck validity_nan 'sample 4: validity = nan where' 4 12 nan
    bad_ck stick_lie 'sample 4: stick_admissible = 0 where its F_n, F_t and mu0 say 1' 4 8 0
    # a plausible value (rotor speed +1000) is caught by the checksum
    bad_ck speed_hash 'damaged: its CRC-32 is' 6 2 -1000 keep-hash
    head -c 300 "$d/good.ck" >"$d/trunc.ck"
    expect_bad "--checkpoint $d/trunc.ck" "truncated" $T --checkpoint "$d/trunc.ck"
    head -c $(($(stat -c %s "$d/good.ck") - 20)) "$d/good.ck" >"$d/trunc2.ck"
    expect_bad "--checkpoint $d/trunc2.ck" "truncated" $T --checkpoint "$d/trunc2.ck"
    { cat "$d/good.ck"; echo x; } >"$d/tail.ck"
    expect_bad "--checkpoint $d/tail.ck" "after the end" $T --checkpoint "$d/tail.ck"
fi
# `good` of a sample the load drives backwards (4-DOF past its stall torque; the rule's
# condition 5) is -1 (TOL_GOOD_DRIVEN) in the row, a value the row check knows: changed
# to 0 or 2 it is refused, and -1 in a study with --allow-driven (its configuration line
# changed and the CRC-32 recomputed, so that the row check itself is tested) is refused
D="tolerance --model 4dof --samples 40 --seed 9 --vary T=uniform:0.0002:0.0008"
if expect_rc 0 $D --checkpoint "$d/drv.ck" --out "$d/drv" --json; then
    # a driven sample: good in every other respect, power_out = -T rotor_speed < 0
    drv=$("$PY" - "$d/drv/samples.csv" <<'PYEOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(next(i for i, r in enumerate(rows) if r["op_class"] == "operating_point" and
           r["stable"] == "true" and r["valid"] == "true" and r["good"] == "false" and
           -float(r["T [N m]"]) * float(r["rotor_speed [1/s]"]) < 0))
PYEOF
    )
    bad_drv() { # NAME REASON VALUE [--allow-driven]
        corrupt "$d/drv.ck" "$d/$1.ck" "$drv" 13 "$3" || { fail "corrupt $1"; return; }
        if [ -n "${4:-}" ]; then
            "$PY" -c 'import sys, zlib, struct
p = sys.argv[1]; b = bytearray(open(p, "rb").read())
k = b.index(b"allow_driven 0\n"); b[k + 13] = ord("1")
end = len(b) - 16
struct.pack_into("<Q", b, end, zlib.crc32(bytes(b[b.index(b"\n") + 1:end])))
open(p, "wb").write(b)' "$d/$1.ck"
        fi
        expect_bad "--checkpoint $d/$1.ck" "$2" $D ${4:-} --checkpoint "$d/$1.ck" --json
    }
    if [ -n "$drv" ]; then
        bad_drv drv_zero "sample $drv: good is 0 but its outputs say 1 \\(or -1: driven\\)" 0
        bad_drv drv_two "sample $drv: good 2 is not 0 or 1 \\(or -1: driven\\)" 2
        bad_drv drv_allowed "sample $drv: good is -1 but its outputs say 1\$" -1 --allow-driven
        # the unchanged row resumes to the same result
        expect_rc 0 $D --checkpoint "$d/drv.ck" --json
    else
        fail "no driven sample in the 4-DOF study"
    fi
fi

finish output_files_cli
