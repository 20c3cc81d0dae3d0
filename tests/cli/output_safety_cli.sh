#!/bin/bash
# Output files are never deleted or written through a symlink, and no two
# outputs of one run are one file.  The reproducers of an independent audit:
#  - a stale stage that is a symlink to a user's directory: its files survive
#    (it used to be emptied: `ln -s userdir .od.usm-new-999999` then
#    `usm tolerance --out od`), for tolerance --out and report --out, and a
#    stale stage that is another user's real directory is not touched either;
#  - --force onto a symlink to a FIFO replaces the link (no write into the
#    pipe, no hang, the --plot log included); a FIFO itself is refused, exit 2;
#  - a tolerance checkpoint's lock path that is a symlink or a directory: exit 2;
#  - --force onto a symlink to a directory (tolerance --out, report --out)
#    replaces the link, the target directory unchanged;
#  - a full disk names the user's DIR/samples.csv, not the hidden stage;
#  - simulate --out X.csv --spectrum X (and map --out m.csv --plot m): refused
#    before the run, exit 2, nothing written; --spectrum . / --plot .: exit 2.
#
# usage: output_safety_cli.sh PATH/TO/usm
set -u
USM=$(realpath "${1:?usage: output_safety_cli.sh PATH/TO/usm}")
# a hang guard: the FIFO cases used to block forever in open(2)
USM_RUN_TIMEOUT=120
. "$(dirname "$0")/../cli_common.sh"
full=$tmp/full
trap 'umount "$full" 2>/dev/null; rm -rf "$tmp"' EXIT

d=$tmp/w
mkdir "$d"
cd "$d" || exit 1

# a directory of the user's, every file of which must survive
userdir() { # NAME FILE...: make it
    local u=$d/$1
    shift
    mkdir "$u"
    for f in "$@"; do echo "mine: $f" >"$u/$f"; done
}
intact() { # NAME FILE...: every file there, unchanged, and nothing else
    local u=$d/$1 what=$1
    shift
    checks=$((checks + 1))
    for f in "$@"; do
        [ "$(cat "$u/$f" 2>/dev/null)" = "mine: $f" ] || { fail "$what/$f was deleted or changed"; return; }
    done
    [ "$(ls -A "$u" | wc -l)" -eq $# ] || fail "$what: files added: $(ls -A "$u")"
}

T="tolerance --samples 64 --vary F0=normal:5%"

# ---- a stale stage that is a symlink: never entered ------------------------------------
userdir victim keep1 samples.csv summary.md
ln -s "$d/victim" .od.usm-new-999999
if expect_rc 0 $T --out od; then
    [ -s od/samples.csv ] || fail "tolerance --out od: no samples.csv"
fi
intact victim keep1 samples.csv summary.md
# the same name with a relative path through another directory
mkdir sub
userdir victim2 samples.csv
ln -s ../victim2 sub/.od2.usm-new-999998
expect_rc 0 $T --out sub/od2
intact victim2 samples.csv

# a stale stage that is a real directory of another user's: not ours, left alone
mkdir .od3.usm-new-999997
echo "theirs" >.od3.usm-new-999997/samples.csv
chown -R nobody .od3.usm-new-999997 2>/dev/null
if [ "$(stat -c %u .od3.usm-new-999997)" != "$(id -u)" ]; then
    expect_rc 0 $T --out od3
    checks=$((checks + 1))
    [ "$(cat .od3.usm-new-999997/samples.csv 2>/dev/null)" = theirs ] ||
        fail "another user's directory under a stage's name was emptied"
fi

# ---- report --out: the stale stage symlink, and --force onto a symlink ------------------
userdir rvictim report.md report.json fig09_speed_frequency_3dof.csv .usm-report
userdir rtarget report.md notes.txt
ln -s "$d/rvictim" .rep.usm-new-999996
ln -s "$d/rtarget" rep
expect_bad "--out" "symbolic link" report --out rep --quick --no-plots
intact rtarget report.md notes.txt
if expect_rc 0 report --out rep --force --quick --no-plots; then
    checks=$((checks + 1))
    [ -d rep ] && [ ! -L rep ] && head -n 1 rep/report.md | grep -q 'usm' ||
        fail "report --force onto a symlink: the link was not replaced by the report's directory"
fi
intact rvictim report.md report.json fig09_speed_frequency_3dof.csv .usm-report
intact rtarget report.md notes.txt

# ---- tolerance --out: --force onto a symlink to a directory -----------------------------
userdir ttarget notes.txt
ln -s "$d/ttarget" tlink
expect_bad "--out" "symbolic link" $T --out tlink
if expect_rc 0 $T --out tlink --force; then
    checks=$((checks + 1))
    [ -d tlink ] && [ ! -L tlink ] && [ -s tlink/samples.csv ] ||
        fail "tolerance --out --force onto a symlink: the link was not replaced"
fi
intact ttarget notes.txt
# no stage of these runs left (the planted ones have pids 9999xx)
checks=$((checks + 1))
left=$(ls -A . sub | grep 'usm-new-' | grep -v 'usm-new-9999[0-9][0-9]$')
[ -z "$left" ] || fail "a stage was left: $left"
# the planted stale symlinks are removed as links (their targets checked above)
checks=$((checks + 1))
[ ! -L .od.usm-new-999999 ] && [ ! -L .rep.usm-new-999996 ] || fail "a stale stage symlink was kept"

# ---- FIFOs: never opened for writing ----------------------------------------------------
M="map --x-points 3 --y-points 2"
mkfifo pipe
ln -s pipe plink.csv
USM_RUN_TIMEOUT=60
if expect_rc 0 $M --out plink.csv --force; then
    checks=$((checks + 1))
    [ -f plink.csv ] && [ ! -L plink.csv ] && [ -p pipe ] ||
        fail "--force onto a symlink to a FIFO: the link was not replaced by a file"
fi
# the --plot log: gnuplot's messages went into the pipe, and the run hung
ln -s pipe sp.log
expect_rc 0 $M --plot sp --force && { [ -f sp.log ] && [ ! -L sp.log ] || fail "--plot log: link not replaced"; }
expect_bad "--out pipe" "named pipe" $M --out pipe --force
expect_bad "--out pipe" "named pipe" $M --out pipe
expect_bad "--out /dev/null" "character device" $M --out /dev/null --force
USM_RUN_TIMEOUT=120
checks=$((checks + 1))
[ -p pipe ] || fail "the FIFO was replaced"

# ---- the checkpoint's lock path ---------------------------------------------------------
ln -s "$d/victim/keep1" .ck1.usm-lock
expect_bad "--checkpoint ck1" "lock file .ck1.usm-lock is a symbolic link" $T --checkpoint ck1
intact victim keep1 samples.csv summary.md
mkdir .ck2.usm-lock
expect_bad "--checkpoint ck2" "lock file .ck2.usm-lock is a directory" $T --checkpoint ck2
mkfifo ck3
USM_RUN_TIMEOUT=60
expect_bad "--checkpoint ck3" "not a regular file" $T --checkpoint ck3
USM_RUN_TIMEOUT=120

# ---- a full disk: the message names DIR/samples.csv, not the stage -----------------------
mkdir "$full"
if mount -t tmpfs -o size=16k tmpfs "$full" 2>/dev/null; then
    expect_rc 1 tolerance --samples 2000 --vary F0=normal:5% --out "$full/od"
    checks=$((checks + 1))
    grep -qF -- "--out $full/od/samples.csv: " "$err" && ! grep -q 'usm-new' "$err" ||
        fail "full disk: the message does not name $full/od/samples.csv"
    [ -z "$(ls -A "$full")" ] || fail "full disk: left $(ls -A "$full")"
    umount "$full"
else
    echo "note: no tmpfs mount (not root?): the full-disk message is not checked"
fi

# ---- outputs of one run that are one file: refused before the run ----------------------
Sim="simulate --duration 2e-4"
expect_bad "--out X.csv" "same file" $Sim --out X.csv --spectrum X --force
expect_bad "--out X.csv" "same file" $Sim --out X.csv --spectrum X
expect_bad "--out ./X.csv" "same file" $Sim --out ./X.csv --spectrum sub/../X
expect_bad "--plot P" "same file" $Sim --out P.gp --plot P
expect_bad "--out m.csv" "same file" $M --out m.csv --plot m
checks=$((checks + 1))
[ ! -e X.csv ] && [ ! -e X.gp ] && [ ! -e P.gp ] && [ ! -e m.csv ] || fail "a refused run wrote a file"
# a prefix that names a directory
expect_bad "--spectrum ." "names a directory" $Sim --spectrum .
expect_bad "--spectrum sub/" "names a directory" $Sim --spectrum sub/
expect_bad "--spectrum sub" "names a directory" $Sim --spectrum sub
expect_bad "--plot ." "names a directory" $M --plot .
checks=$((checks + 1))
[ -z "$(ls -A | grep '^\.\.')" ] && [ ! -e sub/.csv ] || fail "--spectrum .: hidden files written"
# distinct outputs still work
expect_rc 0 $Sim --out Y.csv --spectrum Y_spec && { [ -s Y.csv ] && [ -s Y_spec.csv ] || fail "simulate --out --spectrum"; }

finish output_safety_cli
