#!/bin/bash
# usm tolerance at 10^6 samples: the statistics of a million rows
#   - against numpy/scipy: every quantile (numpy.quantile, linear, the same
#     definition as GSL's) and every Spearman correlation (scipy.stats.rankdata's
#     ranks, correlated in exact integer arithmetic) from the run's own
#     samples.csv, to 1e-14; scipy.stats.spearmanr itself (floating-point
#     sums, off by up to ~1e-11 near |r| = 1) to 1e-9;
#   - byte-identical JSON (without its "timings" line), samples.csv and
#     summary.md between a 2-thread serial run, `mpirun -np 4`, and a study
#     stopped under `mpirun -np 2` after half its blocks and resumed by
#     `mpirun -np 3` (whose blocks lie in both ranks' checkpoint files).
# The cheapest configuration that still exercises every statistic: no
# --from-rest, the default Floquet method, three parameters varied so that
# about 38 % of the samples have a solution (quantiles and 18 Spearman
# correlations over ~380,000 rows, counts over 10^6); about 23 us of CPU per
# sample, so each full run is ~25 CPU-seconds.
#
# usage: tolerance_million.sh PATH/TO/usm [PATH/TO/mpiexec]
# (gnuplot is not run: USM_GNUPLOT names no program, the figures stay scripts)
set -u
USM=${1:?usage: tolerance_million.sh PATH/TO/usm [PATH/TO/mpiexec]}
MPIEXEC=${2:-}
. "$(dirname "$0")/../cli_common.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
# the ranks outnumber the cores: a rank waiting in a collective yields its core
# instead of spinning on it (at 10^5 samples, -np 4 on 2 busy cores took 22.9
# CPU-seconds spinning, 4.6 yielding; the output is the same bytes)
export OMPI_MCA_mpi_yield_when_idle=1
mpi_env="ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

N=${USM_MILLION_SAMPLES:-1000000} # a smaller N only to try the script out
T="tolerance --samples $N --vary F0=normal:10% --vary T=uniform:0:0.02 --vary c_t=normal:5% --spec rotor_speed<=-5"
notimings() { grep -v '^  "timings": ' "$1"; }
same() { # NAME DIR_A DIR_B: JSON, samples.csv and summary.md
    checks=$((checks + 1))
    cmp -s <(notimings "$2/out.json") <(notimings "$3/out.json") || fail "$1: JSON differs"
    cmp -s "$2/run/samples.csv" "$3/run/samples.csv" || fail "$1: samples.csv differs"
    cmp -s "$2/run/summary.md" "$3/run/summary.md" || fail "$1: summary.md differs"
}

mkdir "$tmp/serial"
checks=$((checks + 1))
USM_GNUPLOT=/nonexistent/gnuplot timeout 600 "$USM" $T --threads 2 --json --out "$tmp/serial/run" \
    >"$tmp/serial/out.json" 2>"$err" || fail "serial run: exit $?"

# ---- the figure at 10^6 samples: from the library's 40 counts -------------------------------
# gnuplot on the run's own histograms.gp (the run itself had none) against the
# run's compute time: it read all of samples.csv before (3.5 of 4.8 s at 10^5
# samples, 41 s of CPU at 10^6), now histograms.csv's 40 rows (0.38 s); and
# all of the output, samples.csv (shortest round-trip numbers, formatted on the
# study's threads) included, below 10 % of the computation.
if command -v gnuplot >/dev/null; then
    checks=$((checks + 1))
    # CPU seconds against CPU seconds: the run's own (every thread; its JSON's
    # compute_cpu and output_cpu) and gnuplot's (a child of the script below).
    # Wall seconds would measure the machine's other load as much as the
    # output: on a loaded machine the wall share went from 7 % to 14 %.
    "$PY" - "$tmp/serial/out.json" "$tmp/serial/run/histograms.gp" "$tmp/serial/fig.log" \
        >"$tmp/fig.out" 2>&1 <<'PYEOF' || fail "the figure at 10^6 samples: $(cat "$tmp/fig.out")"
import json, resource, subprocess, sys
o = json.load(open(sys.argv[1]))
t, n = o["timings"], o["samples"]
def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime
c0 = children_cpu()
with open(sys.argv[3], "w") as log:
    subprocess.run(["gnuplot", sys.argv[2]], stdout=log, stderr=log, check=True)
fig = children_cpu() - c0
print(f"compute {t['compute_cpu']:.3g} s of CPU ({t['compute']:.3g} s wall); output "
      f"{t['output_cpu']:.3g} s of CPU ({1e6 * t['output_cpu'] / n:.3g} us a sample, "
      f"{100 * t['output_cpu'] / t['compute_cpu']:.3g} % of compute; wall {t['output']:.3g} s); "
      f"the figure {fig:.3g} s of CPU ({100 * fig / t['compute_cpu']:.3g} % of compute)")
assert fig < 0.1 * t["compute_cpu"], (fig, t["compute_cpu"])
# and the whole of --out (samples.csv on the study's threads, summary.md, the
# counts, the figure) below 10 % of the computation
assert t["output_cpu"] + fig < 0.1 * t["compute_cpu"], (t["output_cpu"], fig, t["compute_cpu"])
PYEOF
    cat "$tmp/fig.out"
fi

# ---- against numpy / scipy ------------------------------------------------------------------
checks=$((checks + 1))
"$PY" - "$tmp/serial/run/samples.csv" "$tmp/serial/out.json" >"$tmp/np.out" 2>&1 <<'PYEOF' || {
import json, math, sys
from fractions import Fraction
import numpy as np
from scipy import stats
rows, o = open(sys.argv[1]).read().split("\n"), json.load(open(sys.argv[2]))
head = rows[0].split(",")
outs = ["theta", "rotor_speed", "F_n", "F_t", "max_modulus", "efficiency"]
params = ["F0", "T", "c_t"]
want = {h.split(" [")[0]: i for i, h in enumerate(head)}
cols = {n: [] for n in params + outs}
for line in rows[1:]:
    if not line:
        continue
    f = line.split(",")
    for n in cols:
        v = f[want[n]]
        cols[n].append(float(v) if v else np.nan)
cols = {n: np.array(v) for n, v in cols.items()}
assert len(cols["F0"]) == o["samples"]
worst_q = worst_r = worst_s = 0.0
rank_mask = ranks = None
for k in outs:
    y = cols[k]
    ok = np.isfinite(y)
    assert o["quantiles"][k]["count"] == ok.sum(), (k, o["quantiles"][k]["count"], ok.sum())
    assert ok.sum() > 0.3 * o["samples"], (k, ok.sum())
    q = np.quantile(y[ok], [0.01, 0.05, 0.5, 0.95, 0.99])  # linear: GSL's definition
    for name, ref in zip(["p1", "p5", "p50", "p95", "p99"], q):
        got = o["quantiles"][k][name]
        err = abs(got - ref) / max(abs(ref), 1e-300)
        worst_q = max(worst_q, err)
        # numpy interpolates with another formula: a few ulps (measured <= 2e-16)
        assert err <= 1e-14, (k, name, got, ref, err)
    # each column ranked once (the samples with a solution are the same for every output):
    # scipy's ranks of the million rows were 7 of the check's 12 CPU-seconds
    v = np.rint(2 * stats.rankdata(y[ok])).astype(np.int64)
    if rank_mask is None or not np.array_equal(rank_mask, ok):
        rank_mask = ok
        ranks = {p: np.rint(2 * stats.rankdata(cols[p][ok])).astype(np.int64) for p in params}
    # scipy.stats.spearmanr of every parameter with the output, in one call
    sp_all = stats.spearmanr(np.column_stack([cols[p][ok] for p in params] + [y[ok]])).correlation
    for i, p in enumerate(params):
        # the reference: scipy's ranks (average for ties), the correlation from them in exact
        # integers (doubled ranks: sum U V - m (m + 1)^2 over the root of the same for U U and V V)
        u = ranks[p]
        m = int(ok.sum())
        c = m * (m + 1) ** 2  # the sums fit int64 below 1.2e6 samples
        suv, suu, svv = int(u @ v) - c, int(u @ u) - c, int(v @ v) - c
        ref = float(Fraction(suv) / Fraction(math.isqrt(suu * svv * 10 ** 40)) * 10 ** 20)
        got = o["influence"][k][p]
        worst_r = max(worst_r, abs(got - ref))
        # ours rounds each sum once, then a product, a root and a quotient: a few ulps
        assert abs(got - ref) <= 1e-14, (k, p, got, ref)
        # scipy.stats.spearmanr itself: floating-point sums, worst near |r| = 1 (measured: 1.05e-11
        # at r = -0.99784, where the exact value from its own ranks is 2 ulps from ours)
        sp = sp_all[i, -1]
        worst_s = max(worst_s, abs(got - sp))
        assert abs(got - sp) <= 1e-9, (k, p, got, sp)
print("numpy/scipy at %d samples: quantiles within %.1e (relative), Spearman within %.1e of the exact "
      "value from scipy's ranks, %.1e of scipy.stats.spearmanr" % (o["samples"], worst_q, worst_r, worst_s))
PYEOF
    failures=$((failures + 1))
    echo "FAIL: numpy/scipy: $(tail -n 5 "$tmp/np.out")"
} && cat "$tmp/np.out"

# ---- MPI: the same bytes --------------------------------------------------------------------
if [ -n "$MPIEXEC" ]; then
    mpi() { # DIR NP ARGS...
        local d=$1 n=$2
        shift 2
        mkdir -p "$d"
        env "$mpi_env" USM_GNUPLOT=/nonexistent/gnuplot timeout 600 "$MPIEXEC" -np $n --oversubscribe \
            -x USM_GNUPLOT "$USM" "$@" >"$d/out.json" 2>"$d/err"
    }
    checks=$((checks + 1))
    mpi "$tmp/np4" 4 $T --threads 1 --json --out "$tmp/np4/run" || fail "mpirun -np 4: exit $?"
    same "mpirun -np 4" "$tmp/serial" "$tmp/np4"
    # 15625 blocks: stopped after 8000 (about half) under 2 ranks, resumed by 3
    half=$(( (N + 127) / 128 ))
    checks=$((checks + 1))
    env "$mpi_env" USM_TOLERANCE_STOP_AFTER_BLOCKS=$half timeout 600 "$MPIEXEC" -np 2 --oversubscribe \
        -x USM_TOLERANCE_STOP_AFTER_BLOCKS "$USM" $T --threads 1 --json --checkpoint "$tmp/ck" \
        >"$out" 2>"$err"
    [ -s "$tmp/ck" ] && [ -s "$tmp/ck.1" ] && grep -q "stopped after $half block" "$err" ||
        fail "mpirun -np 2 stopped after $half blocks"
    checks=$((checks + 1))
    mpi "$tmp/np3" 3 $T --threads 1 --json --checkpoint "$tmp/ck" --out "$tmp/np3/run" ||
        fail "mpirun -np 3 resume: exit $?"
    same "stopped under np 2, resumed under np 3" "$tmp/serial" "$tmp/np3"
fi

finish tolerance_million
