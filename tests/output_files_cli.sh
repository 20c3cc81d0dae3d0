#!/bin/bash
# Outputs whole or absent (issue 22): every single-file output of the command
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
. "$(dirname "$0")/cli_common.sh"

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

# ---- ranges: finite, and their width representable (it used to hang) --------------
expect_bad "from, to" "overflows" sweep --periodic --variant imperfect --over phase_error --from -1e308 --to 1e308 --points 3
expect_bad "from, to" "overflows" sweep --over T --from -1e308 --to 1e308 --points 3
expect_bad "--x-from" "overflows" map --x f --x-from -1e308 --x-to 1e308
expect_bad "--y-from" "overflows" map --y-from -1.7e308 --y-to 1.7e308
expect_bad "--vary T" "overflows" tolerance --samples 3 --vary T=uniform:-1e308:1e308

finish output_files_cli
