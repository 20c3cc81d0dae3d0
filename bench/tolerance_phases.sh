#!/bin/bash
# bench/tolerance_phases.sh: where a large tolerance study's time goes.
# Runs `usm tolerance` at 10^6 and 10^7 samples on 1, 2 and 4 MPI ranks
# (oversubscribed where there are fewer cores; 1 rank is the serial run) with
# --json --out, and prints per run: the wall time, the phases of --json's
# "timings" (rank 0's wall seconds: compute, reduce, statistics, output), the
# peak resident memory of each rank (/usr/bin/time), the statistics per
# sample and the CSV cost per row; then the projection for 10^8 samples on
# 1,000 ranks derived from those figures (see the end of this script and
# docs/tolerance.md, "Large studies and the projection to 1,000 ranks").
#
# The study is bench_tolerance's: 3dof, F0 normal 10 %, c_t normal 5 %, T
# uniform 0..4 mN m, every sample the full stationary search + Floquet.
# gnuplot is not run (USM_GNUPLOT names no program): the output phase is the
# samples.csv and summary.md.
#
# usage: bench/tolerance_phases.sh PATH/TO/usm [SAMPLES...]   (default 1000000 10000000)
#        MPIEXEC=... RANKS="1 2 4" THREADS=1 to change the launcher, ranks, threads
set -u
USM=${1:?usage: tolerance_phases.sh PATH/TO/usm [SAMPLES...]}
shift
SIZES=${*:-1000000 10000000}
RANKS=${RANKS:-1 2 4}
THREADS=${THREADS:-1}
MPIEXEC=${MPIEXEC:-$(command -v mpiexec)}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
export USM_GNUPLOT=/nonexistent/gnuplot
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
V="--vary F0=normal:10% --vary c_t=normal:5% --vary T=uniform:0:0.004"
echo "usm tolerance, 3dof, $V, --threads $THREADS; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)"
printf '%9s %5s %8s %9s %8s %10s %8s %13s %12s %10s\n' samples ranks wall compute reduce statistics output "peak MB/rank" "stats us/smp" "CSV us/row"
for n in $SIZES; do
    for r in $RANKS; do
        rm -rf "$work/out"
        if [ "$r" -eq 1 ]; then
            /usr/bin/time -f '%M' -o "$work/mem.0" "$USM" tolerance --samples $n $V --threads $THREADS \
                --json --out "$work/out" >"$work/json" 2>"$work/err"
        else
            "$MPIEXEC" -np $r --oversubscribe -x USM_GNUPLOT sh -c \
                '/usr/bin/time -f %M -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$work/mem" \
                "$USM" tolerance --samples $n $V --threads $THREADS --json --out "$work/out" \
                >"$work/json" 2>"$work/err"
        fi
        /usr/bin/python3 - "$work/json" $n $r "$work"/mem.* <<'PYEOF' || { echo "run failed: $(grep -v warning "$work/err" | head -3)"; }
import json, sys
o, n, r = json.load(open(sys.argv[1])), int(sys.argv[2]), int(sys.argv[3])
t = o["timings"]
mem = max(int(open(f).read().split()[-1]) for f in sys.argv[4:4 + r]) / 1024.0
wall = sum(t.values())
print("%9d %5d %8.2f %9.2f %8.3f %10.3f %8.3f %13.0f %12.3f %10.3f" % (
    n, r, wall, t["compute"], t["reduce"], t["statistics"], t["output"], mem,
    1e6 * t["statistics"] * r / n, 1e6 * t["output"] * r / n))
PYEOF
        rm -f "$work"/mem.*
    done
done
cat <<'EOF2'

The projection (docs/tolerance.md, "Large studies") from these figures, for 10^8 samples on P = 1,000
ranks of one thread each, n/P = 10^5 samples per rank:
  compute    = (1-rank compute seconds / samples) x 10^5           (the samples are independent)
  statistics = (1-rank statistics seconds per sample) x 10^5        (the local sorts and searches)
               + rounds x latency(P): 64 allreduce rounds per quantile set and per splitter search,
               6 + 3 x (sets of samples) rank exchanges; a cluster allreduce of 1,000 ranks takes
               ~20-50 us, an alltoallv of 10^5 keys per rank ~0.1 s (bandwidth, not latency)
  output     = (CSV seconds per row x 10^5, in parallel) + 10^8 rows x ~190 bytes / file system bandwidth
  reduce     = the load imbalance of one round (8 blocks of 64 samples) plus ~10 allreduces
EOF2
