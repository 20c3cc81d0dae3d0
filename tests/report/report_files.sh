#!/bin/bash
# usm report and its output directory:
#  - a report interrupted while plotting leaves no report and no data under
#    DIR (they are in a stage beside it); the next run replaces it without
#    --force (the .usm-report manifest is written first) and removes the stage;
#  - a re-run interrupted leaves the old report intact, byte for byte (the
#    directory is replaced as a whole); a second run into the same
#    directory at once fails at once with one line;
#  - a symlink planted in the directory is replaced, its target never written;
#  - files the user wrote are still never overwritten without --force;
#  - a gnuplot that exits 0 without writing the images is a failure (exit 1,
#    one line), and report.md then links no image.
#
# usage: report_files.sh PATH/TO/usm
set -u

USM=${1:?usage: report_files.sh PATH/TO/usm}
# a hang guard, not a speed check: a --quick report takes about 2 s in a
# release build but over 60 s under ASan on a loaded 2-core machine (the
# orbits with separation, the squeal's simulations, the design section)
USM_RUN_TIMEOUT=600
. "$(dirname "$0")/../cli_common.sh"

# a "gnuplot" that kills usm while it plots, like a Ctrl-C or a lost session
cat >"$tmp/gnuplot_kill" <<'SH'
#!/bin/sh
kill -KILL "$PPID"
sleep 5
SH
# a "gnuplot" that succeeds without drawing anything
printf '#!/bin/sh\nexit 0\n' >"$tmp/gnuplot_lazy"
chmod +x "$tmp/gnuplot_kill" "$tmp/gnuplot_lazy"

# ---- interrupted during plotting ------------------------------------------------
d=$tmp/interrupted
checks=$((checks + 1))
USM_GNUPLOT=$tmp/gnuplot_kill run report --out "$d" --quick
rc=$?
if [ $rc -ne 137 ] || [ -e "$d/report.md" ] || [ -e "$d/fig10_speed_load_3dof.csv" ] ||
    ! ls -d "$tmp"/.interrupted.usm-new-* >/dev/null 2>&1; then
    fail "killed while plotting: exit $rc, want 137, no report.md and no data under DIR, a stage beside it"
fi
if expect_rc 0 report --out "$d" --quick --no-plots; then
    checks=$((checks + 1))
    [ "$(cat "$out")" = "$d/report.md" ] && [ -s "$d/report.md" ] ||
        fail "the run after an interrupted one did not write report.md"
    ls -d "$tmp"/.interrupted.usm-new-* >/dev/null 2>&1 && fail "the killed run's stage is still there"
fi

# ---- a re-run interrupted: the old report intact, nothing mixed --------------------
# (each report computed costs seconds, a minute under ASan: the cases share runs
# where their checks do not interfere)
plots=(--no-plots)
command -v "${USM_GNUPLOT:-gnuplot}" >/dev/null && plots=()
o=$tmp/old
if expect_rc 0 report --out "$o" --quick --no-plots --set F0=0.3; then
    (cd "$o" && sha256sum -- * .usm-report) >"$tmp/old.sums"
    checks=$((checks + 1))
    USM_GNUPLOT=$tmp/gnuplot_kill run report --out "$o" --quick --set F0=0.4
    rc=$?
    [ $rc -eq 137 ] || fail "re-run killed while plotting: exit $rc, want 137"
    checks=$((checks + 1))
    (cd "$o" && sha256sum -- * .usm-report) | cmp -s - "$tmp/old.sums" ||
        fail "a killed re-run changed the old report: $( (cd "$o" && sha256sum -- * .usm-report) | diff - "$tmp/old.sums" | head -n 4)"
    # the re-run, completed, replaces it as a whole; a symlink planted in the
    # directory is replaced, its target never written.  With gnuplot it draws
    # the figures, whose staleness the lazy gnuplot below is checked against.
    echo precious >"$tmp/precious"
    ln -sf "$tmp/precious" "$o/report_values.csv"
    if expect_rc 0 report --out "$o" --quick "${plots[@]}" --set F0=0.4; then
        checks=$((checks + 1))
        grep -q '"F0": 0.4' "$o/report.json" || fail "the completed re-run's report.json is not F0 = 0.4"
        ls -A "$tmp" | grep -q '^\.old\.usm-new-' && fail "stages left after the re-run"
        checks=$((checks + 1))
        [ "$(cat "$tmp/precious")" = precious ] && [ ! -L "$o/report_values.csv" ] ||
            fail "a symlink in the report directory was written through"
    fi
fi

# ---- two runs into one directory: the second fails at once ---------------------------
printf '#!/bin/sh\nsleep 3\nexit 0\n' >"$tmp/gnuplot_slow"
chmod +x "$tmp/gnuplot_slow"
c=$tmp/concurrent
USM_GNUPLOT=$tmp/gnuplot_slow "$USM" report --out "$c" --quick >/dev/null 2>&1 &
first=$!
for _ in $(seq 100); do ls -d "$tmp"/.concurrent.usm-new-* >/dev/null 2>&1 && break; sleep 0.05; done
expect_bad "--out $c" "another usm report is writing there" report --out "$c" --quick --no-plots
kill $first 2>/dev/null
wait $first 2>/dev/null

# ---- the user's files are kept ------------------------------------------------------
# beside a manifest, a report.md the user wrote is still the user's
rm -f "$d/report.md"
echo "# my notes" >"$d/report.md"
expect_bad 'report.md' 'not written by usm report' report --out "$d" --quick --no-plots
checks=$((checks + 1))
[ "$(cat "$d/report.md")" = "# my notes" ] || fail "a foreign report.md was changed"
# a file of the report's names without any mark of usm is the user's
u=$tmp/user
mkdir "$u"
echo "mine" >"$u/fig09_speed_frequency.gp"
expect_bad 'fig09_speed_frequency.gp' 'no usm report' report --out "$u" --quick --no-plots
# a manifest the user wrote (another first line) does not count
echo "my list" >"$u/.usm-report"
expect_bad 'fig09_speed_frequency.gp' 'no usm report' report --out "$u" --quick --no-plots
checks=$((checks + 1))
[ "$(cat "$u/fig09_speed_frequency.gp")" = "mine" ] || fail "a user's file was changed"

# ---- gnuplot exits 0 without writing images --------------------------------------
l=$tmp/lazy
checks=$((checks + 1))
USM_GNUPLOT=$tmp/gnuplot_lazy run report --out "$l" --quick
rc=$?
if [ $rc -ne 1 ]; then
    fail "gnuplot without images: exit $rc, want 1"
elif [ "$(wc -l <"$err")" -ne 1 ] || ! grep -q '^usm: .*did not write' "$err"; then
    fail "gnuplot without images: want one line '... did not write ...'"
elif grep -qE '\.(png|svg)\)' "$l/report.md"; then
    fail "gnuplot without images: report.md links images that do not exist"
fi
# stale images of an earlier run (the completed re-run's, drawn by gnuplot) do
# not pass for new ones
if [ ${#plots[@]} -eq 0 ] && [ -s "$o/report.md" ]; then
    checks=$((checks + 1))
    USM_GNUPLOT=$tmp/gnuplot_lazy run report --out "$o" --quick
    rc=$?
    [ $rc -eq 1 ] || fail "stale images accepted: exit $rc, want 1"
fi

# ---- the data files: found through USM_DATA_DIR; a broken template is named ----
data=$(cd "$(dirname "$0")/../../data" && pwd)
cp -r "$data" "$tmp/data"
printf 'line one\n{{no_such_number:.3g}}\n' >"$tmp/data/report/report.md.in"
checks=$((checks + 1))
USM_DATA_DIR=$tmp/data run report --out "$tmp/tpl" --quick --no-plots
rc=$?
if [ $rc -ne 1 ] || [ "$(wc -l <"$err")" -ne 1 ] ||
    ! grep -q '^usm: .*report.md.in:2: unknown name {{no_such_number:.3g}}' "$err"; then
    fail "broken template: exit $rc, want 1 and one line naming report.md.in:2"
fi
rm "$tmp/data/paper_values.json"
mkdir "$tmp/empty_data"
checks=$((checks + 1))
USM_DATA_DIR=$tmp/empty_data run report --out "$tmp/nodata" --quick --no-plots
rc=$?
[ $rc -eq 0 ] || fail "USM_DATA_DIR without the files: the source tree's data not used (exit $rc)"

# ---- an installed usm reads share/usm beside it, wherever the tree is moved ----
build=$(dirname "$USM")
if [ -f "$build/cmake_install.cmake" ] && command -v cmake >/dev/null; then
    checks=$((checks + 1))
    if cmake --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log" 2>&1; then
        mv "$tmp/prefix" "$tmp/moved"
        for f in paper_values.json report/report.md.in plots/sweep.gp plots/map_3dof.gp; do
            [ -s "$tmp/moved/share/usm/$f" ] || fail "share/usm/$f not installed"
        done
        # a value changed in the installed copy shows up: that copy is the one read
        sed -i 's/"printed": "9.7 Nmm"/"printed": "9.7 Nmm (installed copy)"/' \
            "$tmp/moved/share/usm/paper_values.json"
        checks=$((checks + 1))
        if "$tmp/moved/bin/usm" report --out "$tmp/inst" --quick --no-plots >"$out" 2>"$err"; then
            grep -q '9.7 Nmm (installed copy)' "$tmp/inst/report.md" ||
                fail "the installed usm did not read share/usm/paper_values.json"
        else
            fail "the installed usm report failed: $(cat "$err")"
        fi
    else
        fail "cmake --install: $(tail -n 3 "$tmp/install.log")"
    fi
fi

finish report_files
