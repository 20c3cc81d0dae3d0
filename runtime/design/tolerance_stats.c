/* The statistics of a tolerance study (usm_tolerance.h; its writers:
 * write/tolerance_out.c), computed where the rows are: every rank
 * holds the rows of its own samples and the ranks exchange counts, order
 * statistics and ranks, never rows (tolerance_comm.h: a serial run is one
 * rank).  Every figure is exact or computed from exact integers, so it does
 * not depend on how the samples are spread over ranks:
 *   - counts, yield and the Wilson interval: sums of integers;
 *   - quantiles: gsl_stats_quantile_from_sorted_data's interpolation between
 *     the order statistics at floor(f (n - 1)) and the next one, each found
 *     exactly by a digit-by-digit search over the doubles' ordered 64-bit
 *     keys (8 rounds of one sum of counts, every local count a binary search
 *     in the rank's sorted keys);
 *   - Spearman: the Pearson correlation of the (tie-averaged) ranks, in
 *     doubled ranks U = 2 R (integers): r = S_uv / sqrt(S_uu S_vv) with S_uv =
 *     sum U V - m (m + 1)^2 summed exactly in 128-bit integers, then rounded
 *     once each.  The ranks come from a sample sort: the rank's keys sorted
 *     (LSD radix sort, O(n)), splitters at the global positions m r / size
 *     (the same exact search), each key sent to the rank of its bucket (equal
 *     keys land in one bucket, so ties are averaged there), ranked there and
 *     its rank sent back.  Memory per rank: O(local samples) (a key repeated
 *     more than samples/ranks times makes its bucket's rank hold all of them).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tolerance_stats.h"
#include "usm_map.h"

typedef uint64_t u64;
__extension__ typedef unsigned __int128 u128;
__extension__ typedef __int128 i128;

/* Two-sided 95 % normal quantile, z = Phi^-1(0.975). */
#define Z95 1.959963984540054

/* The Wilson score interval: unlike the normal (Wald) interval it stays in
 * [0, 1] and keeps its coverage near yields of 0 and 1, where a design
 * study's answers usually are. */
void usm_tolerance_wilson(uint64_t k, uint64_t n, double *lo, double *hi)
{
    if (n == 0) {
        *lo = 0;
        *hi = 1;
        return;
    }
    const double nn = (double)n, ph = (double)k / nn, z2 = Z95 * Z95;
    const double denom = 1.0 + z2 / nn;
    const double center = (ph + z2 / (2.0 * nn)) / denom;
    const double half = Z95 * sqrt(ph * (1.0 - ph) / nn + z2 / (4.0 * nn * nn)) / denom;
    *lo = k == 0 ? 0.0 : fmax(0.0, center - half);
    *hi = k == n ? 1.0 : fmin(1.0, center + half);
}

/* ---- keys and sorting ------------------------------------------------------------- */

#define TOP 0x8000000000000000ULL

/* A finite double as a 64-bit key of the same order (-0 as +0: equal values,
 * equal keys). */
static u64 key_of(double v)
{
    u64 b;
    if (v == 0.0)
        v = 0.0;
    memcpy(&b, &v, sizeof b);
    return b & TOP ? ~b : b | TOP;
}

static double value_of(u64 k)
{
    const u64 b = k & TOP ? k & ~TOP : ~k;
    double v;
    memcpy(&v, &b, sizeof v);
    return v;
}

/* keys[0..n) ascending (LSD radix sort, 8-bit digits; a digit equal in every
 * key is skipped), ix (may be NULL) moved alike; k2, ix2: room for n.  The
 * result is in keys / ix. */
static void radix_sort(u64 *keys, uint32_t *ix, size_t n, u64 *k2, uint32_t *ix2)
{
    static const int D = 8;
    size_t (*count)[256] = calloc((size_t)D, sizeof *count);
    u64 *src = keys, *dst = k2;
    uint32_t *isrc = ix, *idst = ix2;
    if (!count) { /* no 16 kB: a slow but correct insertion sort */
        for (size_t i = 1; i < n; ++i)
            for (size_t j = i; j > 0 && keys[j - 1] > keys[j]; --j) {
                u64 k = keys[j];
                keys[j] = keys[j - 1];
                keys[j - 1] = k;
                if (ix) {
                    uint32_t x = ix[j];
                    ix[j] = ix[j - 1];
                    ix[j - 1] = x;
                }
            }
        return;
    }
    for (size_t i = 0; i < n; ++i)
        for (int d = 0; d < D; ++d)
            ++count[d][(keys[i] >> (8 * d)) & 255];
    for (int d = 0; d < D; ++d) {
        size_t *c = count[d], sum = 0;
        if (n == 0 || c[(src[0] >> (8 * d)) & 255] == n)
            continue; /* one digit value: the pass would not move anything */
        for (int v = 0; v < 256; ++v) {
            const size_t x = c[v];
            c[v] = sum;
            sum += x;
        }
        for (size_t i = 0; i < n; ++i) {
            const size_t to = c[(src[i] >> (8 * d)) & 255]++;
            dst[to] = src[i];
            if (isrc)
                idst[to] = isrc[i];
        }
        u64 *t = src;
        src = dst;
        dst = t;
        uint32_t *it = isrc;
        isrc = idst;
        idst = it;
    }
    if (src != keys) {
        memcpy(keys, src, n * sizeof *keys);
        if (ix)
            memcpy(ix, isrc, n * sizeof *ix);
    }
    free(count);
}

/* Keys <= k in sorted[0..n). */
static size_t upper_bound(const u64 *sorted, size_t n, u64 k)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (sorted[mid] <= k)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Keys < k in sorted[0..n). */
static size_t lower_bound(const u64 *sorted, size_t n, u64 k)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (sorted[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* ---- exact order statistics across ranks -------------------------------------------- */

/* 1 when every rank has ok, else 0 (or -1 when the sum fails). */
static int all_ok(const tol_comm *c, int ok)
{
    u64 bad = !ok;
    if (c->sum_u64(c->ctx, &bad, 1) != 0)
        return -1;
    return bad == 0;
}

/* The keys at the global positions pos[0..n) (0-based, below the number of
 * keys of all ranks) of the ranks' sorted keys, into out: digit by digit
 * from the top (8 bits a round for a few positions, 4 for many), the
 * smallest key with more than pos keys at or below it -- each round one sum
 * of the counts at or below every value of the next digit (a binary search
 * each in this rank's keys), so 8 or 16 rounds in all.  0 or -1 (out of
 * memory, a failed collective). */
static int select_keys(const tol_comm *c, const u64 *sorted, size_t m, const u64 *pos, size_t n,
                       u64 *out, u64 *unused)
{
    const int bits = n <= 64 ? 8 : 4, values = 1 << bits;
    u64 *cnt = malloc((n ? n : 1) * (size_t)values * sizeof *cnt);
    (void)unused;
    if (all_ok(c, cnt != NULL) != 1) {
        free(cnt);
        return -1;
    }
    for (size_t q = 0; q < n; ++q)
        out[q] = 0;
    for (int shift = 64 - bits; shift >= 0; shift -= bits) {
        const u64 low = shift ? (1ULL << shift) - 1 : 0;
        for (size_t q = 0; q < n; ++q)
            for (int d = 0; d < values; ++d)
                cnt[q * (size_t)values + (size_t)d] =
                    upper_bound(sorted, m, out[q] | ((u64)d << shift) | low);
        if (c->sum_u64(c->ctx, cnt, n * (size_t)values) != 0) {
            free(cnt);
            return -1;
        }
        for (size_t q = 0; q < n; ++q) {
            int d = 0; /* the first digit with more than pos keys at or below it */
            while (d < values - 1 && cnt[q * (size_t)values + (size_t)d] <= pos[q])
                ++d;
            out[q] |= (u64)d << shift;
        }
    }
    free(cnt);
    return 0;
}

/* ---- ranks ---------------------------------------------------------------------------- */

typedef struct scratch {
    u64 *k2;       /* radix sort's second buffer */
    uint32_t *ix, *ix2;
} scratch;

/* The doubled ranks U = 2 less + equal + 1 of the keys (m on this rank, in the
 * local order; global count total) into u, over the keys of every rank; keys
 * are left sorted.  0, or -1 (out of memory on some rank, a failed
 * collective). */
static int rank2(const tol_comm *c, u64 *keys, size_t m, u64 total, u64 *u, scratch *s)
{
    uint32_t *ix = s->ix;
    for (size_t i = 0; i < m; ++i)
        ix[i] = (uint32_t)i;
    radix_sort(keys, ix, m, s->k2, s->ix2);
    if (c->size == 1) {
        for (size_t a = 0, b; a < m; a = b) {
            for (b = a + 1; b < m && keys[b] == keys[a];)
                ++b;
            for (size_t i = a; i < b; ++i)
                u[ix[i]] = (u64)(a + b + 1);
        }
        return 0;
    }
    const size_t P = (size_t)c->size, me = (size_t)c->rank;
    u64 *split = calloc(P, sizeof *split), *pos = calloc(P, sizeof *pos),
        *cnt = malloc(P * sizeof *cnt), *scount = malloc(P * sizeof *scount),
        *matrix = malloc(P * P * sizeof *matrix), *rcount = malloc(P * sizeof *rcount);
    u64 *recv = NULL, *sorted = NULL, *ranks = NULL;
    int rc = -1, ok = split && pos && cnt && scount && matrix && rcount;
    if (all_ok(c, ok) != 1)
        goto done;
    for (size_t r = 1; r < P; ++r)
        pos[r - 1] = total * r / P;
    if (select_keys(c, keys, m, pos, P - 1, split, cnt) != 0)
        goto done;
    /* bucket d: split[d - 1] < key <= split[d]; contiguous in the sorted keys */
    for (size_t d = 0, prev = 0; d < P; ++d) {
        const size_t end = d + 1 < P ? upper_bound(keys, m, split[d]) : m;
        scount[d] = end - prev;
        prev = end;
    }
    if (c->allgather(c->ctx, scount, P * sizeof *scount, matrix) != 0)
        goto done;
    u64 nrecv = 0, offset = 0;
    for (size_t r = 0; r < P; ++r) {
        rcount[r] = matrix[r * P + me];
        nrecv += rcount[r];
        for (size_t d = 0; d < me; ++d)
            offset += matrix[r * P + d];
    }
    ok = (recv = malloc((nrecv ? nrecv : 1) * sizeof *recv)) &&
         (sorted = malloc((nrecv ? nrecv : 1) * sizeof *sorted)) &&
         (ranks = malloc((nrecv ? nrecv : 1) * sizeof *ranks));
    if (all_ok(c, ok) != 1 || c->alltoallv(c->ctx, keys, scount, recv, rcount) != 0)
        goto done;
    /* the bucket sorted: a key's rank is the keys before the bucket and the
     * smaller ones in it; ties average over their run */
    {
        u64 *k2 = malloc((nrecv ? nrecv : 1) * sizeof *k2);
        if (all_ok(c, k2 != NULL) != 1) {
            free(k2);
            goto done;
        }
        memcpy(sorted, recv, nrecv * sizeof *sorted);
        radix_sort(sorted, NULL, nrecv, k2, NULL);
        free(k2);
    }
    for (u64 i = 0; i < nrecv; ++i) {
        const u64 lo = lower_bound(sorted, nrecv, recv[i]), hi = upper_bound(sorted, nrecv, recv[i]);
        ranks[i] = 2 * (offset + lo) + (hi - lo) + 1;
    }
    /* back to the keys' ranks, in their sorted order: into recv's room */
    if (c->alltoallv(c->ctx, ranks, rcount, s->k2, scount) != 0)
        goto done;
    for (size_t i = 0; i < m; ++i)
        u[ix[i]] = s->k2[i];
    rc = 0;
done:
    free(split);
    free(pos);
    free(cnt);
    free(scount);
    free(matrix);
    free(rcount);
    free(recv);
    free(sorted);
    free(ranks);
    return rc;
}

/* ---- exact sums of 128-bit integers over ranks --------------------------------------- */

/* x[0..n) summed over the ranks (each split in four 32-bit limbs, summed as
 * 64-bit integers: exact for up to 2^32 ranks).  0 or -1. */
static int sum_u128(const tol_comm *c, u128 *x, size_t n)
{
    u64 *limb = malloc(4 * (n ? n : 1) * sizeof *limb);
    if (all_ok(c, limb != NULL) != 1) {
        free(limb);
        return -1;
    }
    for (size_t i = 0; i < n; ++i)
        for (int l = 0; l < 4; ++l)
            limb[4 * i + (size_t)l] = (u64)(x[i] >> (32 * l)) & 0xffffffffULL;
    if (c->sum_u64(c->ctx, limb, 4 * n) != 0) {
        free(limb);
        return -1;
    }
    for (size_t i = 0; i < n; ++i) {
        x[i] = 0;
        for (int l = 0; l < 4; ++l)
            x[i] += (u128)limb[4 * i + (size_t)l] << (32 * l);
    }
    free(limb);
    return 0;
}

/* Pearson's r of doubled ranks from exact sums: m values, sum U V, sum U^2,
 * sum V^2 (the mean of U and V is m + 1); NaN for a constant column. */
static double spearman(u64 m, u128 uv, u128 uu, u128 vv)
{
    const i128 mean2 = (i128)m * ((i128)m + 1) * ((i128)m + 1);
    const i128 suv = (i128)uv - mean2, suu = (i128)uu - mean2, svv = (i128)vv - mean2;
    if (m < 3 || suu <= 0 || svv <= 0)
        return NAN;
    const double r = (double)suv / sqrt((double)suu * (double)svv);
    return isfinite(r) ? r : NAN;
}

/* ---- the statistics --------------------------------------------------------------------- */

enum { C_GOOD, C_REDRAWN, C_EXISTS, C_STABLE, C_FAILED, C_OP_EXISTS, C_OP_NSR, C_OP_DNS,
       C_OP_UNKNOWN, C_INVALID, C_INV_CONTACT, C_INV_STICK, C_DRIVEN, C_COUNT0,
       C_DIFFER = C_COUNT0 + USM_TOL_NNUMERIC, /* [k][k'] where finite(k) != finite(k') */
       C_N = C_DIFFER + USM_TOL_NNUMERIC * USM_TOL_NNUMERIC };

static int counts(usm_tolerance *t, const tol_comm *c, u64 *v)
{
    const uint64_t n = tol_local_samples(t);
    const int w = t->width;
    memset(v, 0, C_N * sizeof *v);
    for (uint64_t i = 0; i < n; ++i) {
        const double *row = t->rows + i * (uint64_t)w, *out = row + t->nvary;
        v[C_GOOD] += row[TOL_ROW_GOOD(t)] == 1.0;
        /* a count, checked on load (write/tolerance_checkpoint.c); never an out-of-range conversion */
        const double r = row[TOL_ROW_REDRAWS(t)];
        v[C_REDRAWN] += r >= 0.0 && r < (double)TOL_MAX_REDRAWS ? (uint64_t)r : 0;
        v[C_EXISTS] += out[USM_TOL_EXISTS] != 0.0;
        v[C_STABLE] += out[USM_TOL_STABLE] == 1.0;
        v[C_FAILED] += out[USM_TOL_EXISTS] != 0.0 && isnan(out[USM_TOL_MAX_MODULUS]);
        v[C_OP_EXISTS] += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_STABLE;
        v[C_OP_NSR] += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_NO_STABLE_ROOT;
        v[C_OP_DNS] += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_DOES_NOT_START;
        v[C_OP_UNKNOWN] += out[USM_TOL_OP_CLASS] == (double)USM_POINT_OP_UNKNOWN;
        /* NaN (no solution) is neither valid nor invalid */
        v[C_INVALID] += out[USM_TOL_VALIDITY] > (double)USM_VALID;
        v[C_INV_CONTACT] += out[USM_TOL_VALIDITY] == (double)USM_INVALID_CONTACT_OPEN;
        v[C_INV_STICK] += out[USM_TOL_VALIDITY] == (double)USM_INVALID_STICK;
        /* not good only because the load drives the rotor backwards */
        v[C_DRIVEN] += row[TOL_ROW_GOOD(t)] == TOL_GOOD_DRIVEN;
        for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
            const int fk = isfinite(out[k]);
            v[C_COUNT0 + k] += (u64)fk;
            for (int k2 = 0; k2 < k; ++k2)
                v[C_DIFFER + k * USM_TOL_NNUMERIC + k2] += (u64)(fk != isfinite(out[k2]));
        }
    }
    return c->sum_u64(c->ctx, v, C_N);
}

/* The keys of column col over the local samples where output k is finite. */
static size_t column_keys(const usm_tolerance *t, int k, int col, u64 *keys)
{
    const uint64_t n = tol_local_samples(t);
    size_t m = 0;
    for (uint64_t i = 0; i < n; ++i) {
        const double *row = t->rows + i * (uint64_t)t->width;
        if (isfinite(row[t->nvary + k]))
            keys[m++] = key_of(row[col]);
    }
    return m;
}

/* The quantiles of output k from its sorted keys (m here, total in all). */
static int quantiles(usm_tolerance *t, const tol_comm *c, int k, const u64 *sorted, size_t m,
                     u64 total)
{
    u64 pos[10], key[10], cnt[10];
    size_t lhs[5], n = 0;
    double delta[5];
    for (int q = 0; q < 5; ++q)
        t->sum.quantile[k][q] = NAN;
    if (total == 0)
        return 0;
    /* gsl_stats_quantile_from_sorted_data: (1 - delta) x[lhs] + delta x[lhs + 1] */
    for (int q = 0; q < 5; ++q) {
        const double index = USM_TOLERANCE_QUANTILES[q] * (double)(total - 1);
        lhs[q] = (size_t)index;
        delta[q] = index - (double)lhs[q];
        pos[n++] = lhs[q];
        pos[n++] = lhs[q] + 1 < total ? lhs[q] + 1 : lhs[q];
    }
    if (select_keys(c, sorted, m, pos, n, key, cnt) != 0)
        return -1;
    for (int q = 0; q < 5; ++q) {
        const double a = value_of(key[2 * q]), b = value_of(key[2 * q + 1]);
        t->sum.quantile[k][q] =
            lhs[q] == total - 1 ? a : (1 - delta[q]) * a + delta[q] * b;
    }
    return 0;
}

/* The histograms of rotor_speed and max_modulus over every rank's samples
 * (t->hist): the range by an allgather of each rank's extremes, then the
 * bins' counts summed over the ranks, exact integers as every count here.
 * A constant output gets one narrow bin (width 1e-9 of its size) at its
 * value.  0, or -1 when a collective fails or out of memory. */
static int histograms(usm_tolerance *t, const tol_comm *c)
{
    static const int out[2] = {USM_TOL_ROTOR_SPEED, USM_TOL_MAX_MODULUS};
    const uint64_t local = tol_local_samples(t);
    double mine[4], *all = malloc((size_t)c->size * sizeof mine);
    u64 counts[2 * (TOL_HIST_BINS + 1)];
    /* every rank takes part in the collectives below, or none does */
    int rc = all_ok(c, all != NULL) == 1 ? 0 : -1;
    for (int h = 0; h < 2; ++h) {
        mine[2 * h] = HUGE_VAL, mine[2 * h + 1] = -HUGE_VAL;
        for (uint64_t i = 0; i < local; ++i) {
            const double v = t->rows[i * (uint64_t)t->width + (uint64_t)(t->nvary + out[h])];
            if (isfinite(v))
                mine[2 * h] = fmin(mine[2 * h], v), mine[2 * h + 1] = fmax(mine[2 * h + 1], v);
        }
    }
    if (rc == 0 && c->allgather(c->ctx, mine, sizeof mine, all) != 0)
        rc = -1;
    memset(counts, 0, sizeof counts);
    for (int h = 0; h < 2 && rc == 0; ++h) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (int r = 0; r < c->size; ++r)
            lo = fmin(lo, all[4 * r + 2 * h]), hi = fmax(hi, all[4 * r + 2 * h + 1]);
        if (!(lo <= hi)) /* no sample has this output */
            lo = hi = 0.0;
        else if (!(hi > lo))
            hi = lo + fmax(fabs(lo), 1e-300) * 1e-9 * TOL_HIST_BINS;
        t->hist[h].lo = lo, t->hist[h].hi = hi;
        const double w = (hi - lo) / TOL_HIST_BINS;
        u64 *cnt = counts + h * (TOL_HIST_BINS + 1);
        for (uint64_t i = 0; i < local && w > 0; ++i) {
            const double v = t->rows[i * (uint64_t)t->width + (uint64_t)(t->nvary + out[h])];
            if (!isfinite(v))
                continue;
            long b = (long)floor((v - lo) / w);
            b = b < 0 ? 0 : b >= TOL_HIST_BINS ? TOL_HIST_BINS - 1 : b; /* hi in the last */
            ++cnt[b];
            ++cnt[TOL_HIST_BINS];
        }
    }
    if (rc == 0 && c->sum_u64(c->ctx, counts, sizeof counts / sizeof counts[0]) != 0)
        rc = -1;
    for (int h = 0; h < 2 && rc == 0; ++h) {
        memcpy(t->hist[h].count, counts + h * (TOL_HIST_BINS + 1), TOL_HIST_BINS * sizeof(u64));
        t->hist[h].total = counts[h * (TOL_HIST_BINS + 1) + TOL_HIST_BINS];
    }
    free(all);
    return rc;
}

int tol_finish(usm_tolerance *t, const tol_comm *c)
{
    usm_tolerance_summary *s = &t->sum;
    const uint64_t n = t->opt.samples, local = tol_local_samples(t);
    const size_t cap = local ? (size_t)local : 1;
    const int nv = t->nvary;
    u64 v[C_N];
    double start = tol_now();
    scratch sc = {malloc(cap * sizeof(u64)), malloc(cap * sizeof(uint32_t)),
                  malloc(cap * sizeof(uint32_t))};
    u64 *keys = malloc(cap * sizeof *keys), *ov = malloc(cap * sizeof *ov),
        *pu = malloc((size_t)nv * cap * sizeof *pu);
    int ok = sc.k2 && sc.ix && sc.ix2 && keys && ov && pu, leader[USM_TOL_NNUMERIC];
    int rc = all_ok(c, ok) == 1 && counts(t, c, v) == 0 ? USM_OK : USM_EFAILED;
    if (rc != USM_OK)
        goto done;
    s->samples = n;
    s->seed = t->opt.seed;
    s->good = v[C_GOOD];
    s->redrawn = v[C_REDRAWN];
    s->exists = v[C_EXISTS];
    s->stable = v[C_STABLE];
    s->failed = v[C_FAILED];
    s->op_exists = v[C_OP_EXISTS];
    s->op_no_stable_root = v[C_OP_NSR];
    s->op_does_not_start = v[C_OP_DNS];
    s->op_unknown = v[C_OP_UNKNOWN];
    s->invalid = v[C_INVALID];
    s->invalid_contact_open = v[C_INV_CONTACT];
    s->invalid_stick = v[C_INV_STICK];
    s->driven = v[C_DRIVEN];
    s->yield = (double)s->good / (double)n;
    usm_tolerance_wilson(s->good, n, &s->yield_lo, &s->yield_hi);
    t->timings.reduce += tol_now() - start;
    start = tol_now();
    /* outputs finite on the same samples share the varied parameters' ranks */
    for (int k = 0; k < USM_TOL_NNUMERIC; ++k) {
        s->count[k] = v[C_COUNT0 + k];
        leader[k] = k;
        for (int k2 = 0; k2 < k && leader[k] == k; ++k2)
            if (v[C_DIFFER + k * USM_TOL_NNUMERIC + k2] == 0)
                leader[k] = leader[k2];
    }
    for (int k = 0; k < USM_TOL_NNUMERIC && rc == USM_OK; ++k) {
        const u64 total = s->count[k];
        size_t m = 0;
        u128 sums[1 + 3 * USM_NPARAMS];
        if (leader[k] == k) /* the parameters' ranks over this set of samples */
            for (int j = 0; j < nv && rc == USM_OK; ++j) {
                m = column_keys(t, k, j, keys);
                if (total && rank2(c, keys, m, total, pu + (size_t)j * cap, &sc) != 0)
                    rc = USM_EFAILED;
            }
        m = column_keys(t, k, nv + k, keys);
        if (rc != USM_OK || (total && rank2(c, keys, m, total, ov, &sc) != 0) ||
            quantiles(t, c, k, keys, m, total) != 0) {
            rc = USM_EFAILED;
            break;
        }
        /* the parameters' ranks are those of leader[k]'s samples, the same ones */
        memset(sums, 0, sizeof sums);
        for (size_t i = 0; i < m; ++i)
            sums[0] += (u128)ov[i] * ov[i];
        for (int j = 0; j < nv; ++j) {
            const u64 *u = pu + (size_t)j * cap;
            u128 uv = 0, uu = 0;
            for (size_t i = 0; i < m; ++i) {
                uv += (u128)u[i] * ov[i];
                uu += (u128)u[i] * u[i];
            }
            sums[1 + 3 * j] = uv;
            sums[2 + 3 * j] = uu;
        }
        if (sum_u128(c, sums, 1 + 3 * (size_t)nv) != 0) {
            rc = USM_EFAILED;
            break;
        }
        for (int j = 0; j < nv; ++j)
            t->influence[k][j] = spearman(total, sums[1 + 3 * j], sums[2 + 3 * j], sums[0]);
    }
    if (rc == USM_OK && histograms(t, c) != 0)
        rc = USM_EFAILED;
done:
    if (rc != USM_OK)
        snprintf(t->msg, USM_MSG_LEN, "out of memory for the statistics%s",
                 c->size > 1 ? " (or a failed MPI collective)" : "");
    free(sc.k2);
    free(sc.ix);
    free(sc.ix2);
    free(keys);
    free(ov);
    free(pu);
    t->timings.statistics += tol_now() - start;
    t->have_result = rc == USM_OK;
    return rc;
}

/* ---- one rank ---------------------------------------------------------------------------- */

static int serial_sum(void *ctx, uint64_t *v, size_t n)
{
    (void)ctx, (void)v, (void)n;
    return 0;
}

static int serial_allgather(void *ctx, const void *mine, size_t bytes, void *all)
{
    (void)ctx;
    memcpy(all, mine, bytes);
    return 0;
}

static int serial_alltoallv(void *ctx, const uint64_t *send, const uint64_t *scount,
                            uint64_t *recv, const uint64_t *rcount)
{
    (void)ctx, (void)rcount;
    memcpy(recv, send, scount[0] * sizeof *send);
    return 0;
}

const tol_comm tol_comm_serial = {0, 1, NULL, serial_sum, serial_allgather, serial_alltoallv};
