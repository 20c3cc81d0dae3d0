/* The rows of a tolerance study (tolerance_rows.h): what their columns are
 * called, how many samples each block holds, and moving blocks of rows. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <string.h>
#include <time.h>

#include "tolerance_rows.h"
#include "yield_rule.h"

static const char *const output_names[USM_TOL_NOUTPUTS] = {
    "theta", "rotor_speed", "F_n", "F_t", "max_modulus", "efficiency",
    "stable", "stick_admissible", "exists", "operating_point", "op_class", "validity"};
static const char *const output_units[USM_TOL_NOUTPUTS] = {
    "rad", "1/s", "N", "N", "1", "1", NULL, NULL, NULL, NULL, NULL, NULL};

const double USM_TOLERANCE_QUANTILES[5] = {0.01, 0.05, 0.5, 0.95, 0.99};

const char *usm_tolerance_output_name(int k)
{
    return k >= 0 && k < USM_TOL_NOUTPUTS ? output_names[k] : NULL;
}

const char *usm_tolerance_output_unit(int k)
{
    return k >= 0 && k < USM_TOL_NOUTPUTS ? output_units[k] : NULL;
}

int usm_tolerance_output_find(const char *name)
{
    for (int k = 0; name && k < USM_TOL_NOUTPUTS; ++k)
        if (strcmp(output_names[k], name) == 0)
            return k;
    return -1;
}

uint64_t tol_block_size(const usm_tolerance *t, uint64_t b)
{
    const uint64_t first = b * USM_TOLERANCE_BLOCK, n = t->opt.samples - first;
    return n < USM_TOLERANCE_BLOCK ? n : USM_TOLERANCE_BLOCK;
}

void tol_owned(uint64_t nblocks, int r, int size, uint64_t *lo, uint64_t *hi)
{
    *lo = nblocks * (uint64_t)r / (uint64_t)size;
    *hi = nblocks * (uint64_t)(r + 1) / (uint64_t)size;
}

double *tol_block_rows(const usm_tolerance *t, uint64_t b)
{
    return t->rows + (b - t->blo) * USM_TOLERANCE_BLOCK * (uint64_t)t->width;
}

uint64_t tol_local_samples(const usm_tolerance *t)
{
    const uint64_t first = t->blo * USM_TOLERANCE_BLOCK, end = t->bhi * USM_TOLERANCE_BLOCK;
    if (t->bhi <= t->blo)
        return 0;
    return (end < t->opt.samples ? end : t->opt.samples) - first;
}

uint64_t tol_pack_size(const usm_tolerance *t, const uint64_t *blocks, size_t n)
{
    uint64_t samples = 0;
    for (size_t k = 0; k < n; ++k)
        samples += tol_block_size(t, blocks[k]);
    return samples * (uint64_t)t->width;
}

void tol_unpack(usm_tolerance *t, const uint64_t *blocks, size_t n, const double *pack)
{
    for (size_t k = 0; k < n; ++k) {
        const uint64_t cnt = tol_block_size(t, blocks[k]) * (uint64_t)t->width;
        memcpy(tol_block_rows(t, blocks[k]), pack,
               cnt * sizeof *pack);
        pack += cnt;
        t->done[blocks[k]] = 1;
    }
}

size_t tol_pending(const usm_tolerance *t, uint64_t *list)
{
    size_t n = 0;
    for (uint64_t b = t->blo; b < t->bhi; ++b)
        if (!t->done[b])
            list[n++] = b;
    return n;
}

double tol_cpu(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double tol_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int tol_meets_specs(const usm_tolerance *t, const double *out)
{
    for (int s = 0; s < t->nspec; ++s) {
        const double v = out[t->spec[s].output];
        if (!(t->spec[s].upper ? v <= t->spec[s].bound : v >= t->spec[s].bound))
            return 0; /* NaN (the output does not exist) fails every spec */
    }
    return 1;
}

int tol_row_allows_good(const usm_tolerance *t, const double *row)
{
    const double *out = row + t->nvary;
    /* yield_rule.h without its last part (the row holds no power_out) */
    return yield_sample_good(!isnan(out[USM_TOL_OPERATING_POINT]), out[USM_TOL_MAX_MODULUS],
                             out[USM_TOL_VALIDITY] == (double)USM_VALID,
                             tol_meets_specs(t, out), NAN, 1, NULL);
}
