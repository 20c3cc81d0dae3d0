/* The checkpoint file of a tolerance study (usm_tolerance.h).
 *
 * Layout: the text line MAGIC, the study's configuration (tolerance.c,
 * build_config: one "key value" line each, numbers exact in %a), the line
 * "end", then binary in the host's byte order: ORDER (a uint64 that reads
 * back only on a host of the same byte order), the number of blocks stored,
 * each block as its index (uint64) and its rows (doubles, bit for bit), the
 * FNV-1a hash of those bytes from the count on (uint64; format 2, absent in
 * format 1, which is still read), and ORDER again (a truncated file is
 * refused, not half read).  Every row read is checked (check_row) before it
 * is used: the varied parameters physical, the outputs finite or NaN as a
 * computed row has them, the yes/no values 0 or 1, stick_admissible and the
 * validity as the row's own F_n, F_t and mu0 imply, `good` as the study
 * would compute it, the redraws a whole number below TOL_MAX_REDRAWS -- a
 * corrupted or hand-made file is refused naming the sample, never turned
 * into a result (nor into an out-of-range float-to-integer conversion).  It is written to
 * a temporary beside FILE (core/outfile.c: a fresh name, created with
 * O_EXCL|O_NOFOLLOW, so never through a symlink) and renamed over FILE, so
 * FILE is always one complete write and a symlink is replaced, never
 * written through. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sys/stat.h>

#include "core/outfile.h"
#include "tolerance_io.h"
#include "usm_map.h" /* usm_point_op_class */

static const char MAGIC[] = "usm tolerance checkpoint 2\n";
static const char MAGIC1[] = "usm tolerance checkpoint 1\n"; /* without the hash */

/* FNV-1a, 64 bits, continued from h over n bytes. */
static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *c = data;
    for (size_t i = 0; i < n; ++i)
        h = (h ^ c[i]) * 0x100000001b3ULL;
    return h;
}
#define FNV_START 0xcbf29ce484222325ULL

/* Whether x is 0 or 1. */
static int yes_no(double x)
{
    return x == 0.0 || x == 1.0;
}

/* NULL when the row of sample i is one the study could have computed, else
 * the reason (into why). */
static const char *check_row(const usm_tolerance *t, uint64_t i, const double *row,
                             char why[USM_MSG_LEN])
{
    const double *out = row + t->nvary;
    const double exists = out[USM_TOL_EXISTS], mm = out[USM_TOL_MAX_MODULUS];
    const double good = row[TOL_ROW_GOOD(t)], redraws = row[TOL_ROW_REDRAWS(t)];
    usm_params q = t->p;
    char perr[USM_MSG_LEN];
    for (int j = 0; j < t->nvary; ++j) {
        if (!isfinite(row[j])) {
            snprintf(why, USM_MSG_LEN, "sample %llu: %s = %g is not a finite number",
                     (unsigned long long)i, t->vary[j].param->name, row[j]);
            return why;
        }
        *usm_params_field(&q, t->vary[j].param) = row[j];
        usm_params_couple(t->m, &q, usm_param_index(t->vary[j].param));
    }
    if (usm_params_check(&q, t->m, perr) != USM_OK) {
        snprintf(why, USM_MSG_LEN, "sample %llu: not physical (%.120s)", (unsigned long long)i,
                 perr);
        return why;
    }
    /* redraws first: it becomes an integer */
    if (!(redraws >= 0.0 && redraws < (double)TOL_MAX_REDRAWS && redraws == floor(redraws))) {
        snprintf(why, USM_MSG_LEN, "sample %llu: redraws %g is not a whole number 0 ... %d",
                 (unsigned long long)i, redraws, TOL_MAX_REDRAWS - 1);
        return why;
    }
    if (!yes_no(exists) || !yes_no(good)) {
        snprintf(why, USM_MSG_LEN, "sample %llu: %s %g is not 0 or 1", (unsigned long long)i,
                 yes_no(exists) ? "good" : "exists", yes_no(exists) ? good : exists);
        return why;
    }
    for (int k = 0; k < USM_TOL_NOUTPUTS; ++k) {
        const double v = out[k];
        const char *name = usm_tolerance_output_name(k);
        double want = NAN; /* the value the row's other outputs imply, where they do */
        int ok;
        if (k == USM_TOL_EXISTS)
            continue;
        if (k == USM_TOL_OP_CLASS) { /* a usm_point_op_class, defined for every sample */
            ok = v >= USM_POINT_OP_STABLE && v <= USM_POINT_OP_NO_SOLUTION && v == floor(v) &&
                 (v == USM_POINT_OP_NO_SOLUTION) == (exists == 0.0);
        } else if (k == USM_TOL_OPERATING_POINT) { /* a root index, or NaN: none */
            ok = isnan(v) || (v >= 0.0 && v < 1e6 && v == floor(v) && exists == 1.0);
        } else if (exists == 0.0)
            ok = isnan(v); /* no solution: no value */
        else if (k == USM_TOL_MAX_MODULUS)
            ok = isnan(v) || (isfinite(v) && v >= 0.0); /* NaN: the multipliers failed */
        else if (k == USM_TOL_STABLE)
            ok = isnan(mm) ? isnan(v) : v == (mm < 1.0);
        else if (k == USM_TOL_STICK_ADMISSIBLE) {
            /* steady.c: F_n > 0 and |F_t| <= mu0 F_n, from the row's own forces */
            want = out[USM_TOL_F_N] > 0 &&
                   fabs(out[USM_TOL_F_T]) <= usm_params_get(&q, &usm_param_table[USM_P_mu0]) *
                                                 out[USM_TOL_F_N];
            ok = v == want;
        } else if (k == USM_TOL_VALIDITY) {
            /* usm_validity from the row's own F_n and stick_admissible (both checked
             * above): the contact open, else a stick model past its limit */
            want = !(out[USM_TOL_F_N] > 0) ? USM_INVALID_CONTACT_OPEN
                   : !t->m->slip && out[USM_TOL_STICK_ADMISSIBLE] == 0.0 ? USM_INVALID_STICK
                                                                         : USM_VALID;
            ok = v == want;
        } else if (k == USM_TOL_EFFICIENCY)
            ok = !isinf(v); /* NaN where power_in <= 0 */
        else
            ok = isfinite(v);
        if (!ok && !isnan(want)) {
            snprintf(why, USM_MSG_LEN, "sample %llu: %s = %g where its F_n, F_t and mu0 say %g",
                     (unsigned long long)i, name, v, want);
            return why;
        }
        if (!ok) {
            snprintf(why, USM_MSG_LEN, "sample %llu: %s = %g where %s", (unsigned long long)i,
                     name, v, exists == 0.0 ? "no solution exists" : "the study computes no such value");
            return why;
        }
    }
    /* good: an operating point (whose max_modulus the row holds) that meets the
     * specs and is valid */
    const int computed = !isnan(out[USM_TOL_OPERATING_POINT]) && isfinite(mm) && mm < 1.0 &&
                         tol_meets_specs(t, out) && out[USM_TOL_VALIDITY] == (double)USM_VALID;
    if (good != (double)computed) {
        snprintf(why, USM_MSG_LEN, "sample %llu: good is %g but its outputs say %d",
                 (unsigned long long)i, good, computed);
        return why;
    }
    return NULL;
}
static const uint64_t ORDER = 0x0102030405060708ULL;

/* The first line where two configuration texts differ, into a and b. */
static void first_difference(const char *x, const char *y, char a[80], char b[80])
{
    while (*x && *y) {
        const size_t nx = strcspn(x, "\n"), ny = strcspn(y, "\n");
        if (nx != ny || memcmp(x, y, nx) != 0) {
            snprintf(a, 80, "%.*s", (int)(nx < 79 ? nx : 79), x);
            snprintf(b, 80, "%.*s", (int)(ny < 79 ? ny : 79), y);
            return;
        }
        x += nx + (x[nx] == '\n');
        y += ny + (y[ny] == '\n');
    }
    snprintf(a, 80, "%.*s", 79, *x ? x : "(end)");
    snprintf(b, 80, "%.*s", 79, *y ? y : "(end)");
    a[strcspn(a, "\n")] = '\0';
    b[strcspn(b, "\n")] = '\0';
}

static int refuse(usm_tolerance *t, const char *why)
{
    snprintf(t->msg, USM_MSG_LEN, "checkpoint %.60s: %.180s", t->opt.checkpoint, why);
    return USM_EINPUT;
}

int tol_checkpoint_load(usm_tolerance *t)
{
    const char *path = t->opt.checkpoint;
    FILE *f = fopen(path, "rb");
    char line[512];
    size_t clen = strlen(t->config), have = 0;
    char *text = NULL;
    uint64_t order = 0, n = 0;
    int status = USM_OK;
    if (!f) {
        struct stat st;
        char why[USM_MSG_LEN];
        if (errno != ENOENT) {
            snprintf(t->msg, USM_MSG_LEN, "checkpoint %.120s: %s", path, strerror(errno));
            return USM_EINPUT;
        }
        /* a first run: the file must be creatable now, not at the first write */
        if (lstat(path, &st) == 0)
            return refuse(t, "a symbolic link to nothing; refusing to write through it");
        if (usm_outfile_check(path, 1, why, sizeof why) != USM_OK) {
            snprintf(t->msg, USM_MSG_LEN, "checkpoint %.200s", why);
            return USM_EINPUT;
        }
        return USM_OK;
    }
    if (!fgets(line, sizeof line, f) || (strcmp(line, MAGIC) != 0 && strcmp(line, MAGIC1) != 0)) {
        fclose(f);
        return refuse(t, "not a usm tolerance checkpoint (refusing to overwrite it)");
    }
    const int hashed = strcmp(line, MAGIC) == 0;
    uint64_t hash = FNV_START, stored;
    if (!(text = malloc(clen + 1))) {
        fclose(f);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    text[0] = '\0';
    /* the configuration, up to "end" */
    int ended = 0;
    while (fgets(line, sizeof line, f) && !(ended = strcmp(line, "end\n") == 0)) {
        const size_t l = strlen(line);
        if (have + l > clen) {
            have = clen + 1; /* longer than this study's: differs */
            break;
        }
        memcpy(text + have, line, l + 1);
        have += l;
    }
    if (!ended && have <= clen) {
        status = refuse(t, "truncated (in its configuration)");
    } else if (have != clen || memcmp(text, t->config, clen) != 0) {
        char a[80], b[80], why[USM_MSG_LEN];
        if (have > clen)
            snprintf(a, sizeof a, "a longer configuration"), snprintf(b, sizeof b, "%s", "");
        else
            first_difference(text, t->config, a, b);
        snprintf(why, sizeof why, "written by another study (it has \"%.70s\" where this run "
                 "has \"%.70s\"); use another file or remove it", a, b);
        status = refuse(t, why);
    } else if (fread(&order, sizeof order, 1, f) != 1 || order != ORDER ||
               fread(&n, sizeof n, 1, f) != 1) {
        status = refuse(t, "truncated or from a host of another byte order");
    } else if (n > t->nblocks) {
        char why[USM_MSG_LEN];
        snprintf(why, sizeof why, "corrupt: %llu blocks stored, the study has %llu",
                 (unsigned long long)n, (unsigned long long)t->nblocks);
        status = refuse(t, why);
    }
    hash = fnv(hash, &n, sizeof n);
    for (uint64_t k = 0; status == USM_OK && k < n; ++k) {
        uint64_t b;
        char why[USM_MSG_LEN];
        if (fread(&b, sizeof b, 1, f) != 1) {
            status = refuse(t, "truncated");
            break;
        }
        if (b >= t->nblocks || t->done[b]) {
            snprintf(why, sizeof why, "corrupt: block index %llu %s", (unsigned long long)b,
                     b >= t->nblocks ? "beyond the study" : "stored twice");
            status = refuse(t, why);
            break;
        }
        const size_t cnt = (size_t)(tol_block_size(t, b) * (uint64_t)t->width);
        double *rows = t->rows + b * USM_TOLERANCE_BLOCK * (uint64_t)t->width;
        if (fread(rows, sizeof(double), cnt, f) != cnt) {
            status = refuse(t, "truncated");
            break;
        }
        hash = fnv(fnv(hash, &b, sizeof b), rows, cnt * sizeof(double));
        for (uint64_t i = 0; i < tol_block_size(t, b); ++i) {
            const char *bad = check_row(t, b * USM_TOLERANCE_BLOCK + i,
                                        rows + i * (uint64_t)t->width, why);
            if (bad) {
                char w2[USM_MSG_LEN];
                snprintf(w2, sizeof w2, "corrupt: %.200s", bad);
                status = refuse(t, w2);
                break;
            }
        }
        t->done[b] = status == USM_OK;
    }
    if (status == USM_OK && hashed &&
        (fread(&stored, sizeof stored, 1, f) != 1 || stored != hash))
        status = refuse(t, "corrupt: its data do not match their hash");
    if (status == USM_OK && (fread(&order, sizeof order, 1, f) != 1 || order != ORDER))
        status = refuse(t, "truncated");
    if (status == USM_OK && fgetc(f) != EOF)
        status = refuse(t, "corrupt: data after the end");
    fclose(f);
    free(text);
    if (status != USM_OK) {
        memset(t->done, 0, t->nblocks);
        return status;
    }
    t->sum.resumed_blocks = n;
    return USM_OK;
}

int tol_checkpoint_write(usm_tolerance *t)
{
    const char *path = t->opt.checkpoint;
    char tmp[USM_OUTFILE_PATH], why[USM_MSG_LEN];
    uint64_t n = 0;
    FILE *f;
    int bad, fd, status;
    const double start = tol_now();
    if ((fd = usm_outfile_open(path, 1, tmp, why, sizeof why, &status)) < 0) {
        snprintf(t->msg, USM_MSG_LEN, "checkpoint %.200s", why);
        return USM_EFAILED;
    }
    if (!(f = fdopen(fd, "wb"))) {
        snprintf(t->msg, USM_MSG_LEN, "checkpoint %.120s: %s", path, strerror(errno));
        close(fd);
        if (tmp[0])
            unlink(tmp);
        return USM_EFAILED;
    }
    for (uint64_t b = 0; b < t->nblocks; ++b)
        n += t->done[b];
    bad = fputs(MAGIC, f) < 0 || fputs(t->config, f) < 0 || fputs("end\n", f) < 0 ||
          fwrite(&ORDER, sizeof ORDER, 1, f) != 1 || fwrite(&n, sizeof n, 1, f) != 1;
    uint64_t hash = fnv(FNV_START, &n, sizeof n);
    for (uint64_t b = 0; !bad && b < t->nblocks; ++b) {
        if (!t->done[b])
            continue;
        const size_t cnt = (size_t)(tol_block_size(t, b) * (uint64_t)t->width);
        const double *rows = t->rows + b * USM_TOLERANCE_BLOCK * (uint64_t)t->width;
        bad = fwrite(&b, sizeof b, 1, f) != 1 || fwrite(rows, sizeof(double), cnt, f) != cnt;
        hash = fnv(fnv(hash, &b, sizeof b), rows, cnt * sizeof(double));
    }
    bad = bad || fwrite(&hash, sizeof hash, 1, f) != 1 ||
          fwrite(&ORDER, sizeof ORDER, 1, f) != 1 || fflush(f) != 0 ||
          fsync(fileno(f)) != 0;
    if ((fclose(f) != 0) | bad) {
        snprintf(t->msg, USM_MSG_LEN, "checkpoint %.120s: write error: %s", path,
                 strerror(errno));
        if (tmp[0])
            unlink(tmp);
        return USM_EFAILED;
    }
    if (usm_outfile_place(tmp, path, 1, why, sizeof why) != USM_OK) {
        snprintf(t->msg, USM_MSG_LEN, "checkpoint %.200s", why);
        return USM_EFAILED;
    }
    t->last_write = tol_now();
    t->write_seconds = t->last_write - start;
    return USM_OK;
}
