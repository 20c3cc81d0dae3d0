/* The checkpoint files of a tolerance study (usm_tolerance.h).
 *
 * One file per rank: rank 0's is FILE itself (the serial run's
 * only one), rank r's FILE.r; each holds the blocks its rank owns
 * (tol_owned).  Layout (format 3): the text line MAGIC; "usm VERSION" (the
 * library's version: another version's file is refused, since another build
 * may compute other bits); "part R of S" (rank R of S ranks wrote it, so it
 * holds blocks of [nblocks R / S, nblocks (R + 1) / S) only); the study's
 * configuration (tolerance.c, build_config: one "key value" line each,
 * numbers exact in %a); the line "end"; then binary in the host's byte order:
 * ORDER (a uint64 that reads back only on a host of the same byte order), the
 * number of blocks stored, each block as its index (uint64) and its rows
 * (doubles, bit for bit), the CRC-32 (zlib's crc32, the ISO-HDLC polynomial,
 * as a uint64) of every byte after the MAGIC line up to it, and ORDER again.
 * A resume reads every file of the set (FILE's part line says how many a run
 * wrote; missing ones are skipped) whose blocks overlap this rank's, so a run
 * may resume with another number of ranks.  Refused, with one line (exit 2),
 * never used: a file of another format or version, of another configuration
 * (seed, parameters, ...), truncated, or damaged -- its checksum, or any row
 * that the study could not have computed (check_row: the varied parameters
 * physical, the outputs finite or NaN as a computed row has them, the yes/no
 * values 0 or 1, stick_admissible and the validity as the row's own F_n, F_t
 * and mu0 imply, `good` as the study would compute it (1, or -1 for a sample
 * the load drives, TOL_GOOD_DRIVEN, only where the outputs allow it; -1 never
 * with allow_driven), the redraws a whole
 * number below TOL_MAX_REDRAWS; never an out-of-range float-to-integer
 * conversion).  Each file is written to a temporary beside it (core/outfile.c:
 * a fresh name, created with O_EXCL|O_NOFOLLOW, so never through a symlink)
 * and renamed over it, so it is always one complete write.  Files FILE.r of
 * an earlier run with more ranks than this one stay (their blocks are in this
 * run's files too); remove them after the run. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sys/stat.h>

#include <zlib.h>

#include "core/outfile.h"
#include "tolerance_checkpoint.h"
#include "usm_map.h" /* usm_point_op_class */

static const char MAGIC[] = "usm tolerance checkpoint 3\n";

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
    if (!yes_no(exists) || !(yes_no(good) || good == TOL_GOOD_DRIVEN)) {
        snprintf(why, USM_MSG_LEN, "sample %llu: %s %g is not 0 or 1%s", (unsigned long long)i,
                 yes_no(exists) ? "good" : "exists", yes_no(exists) ? good : exists,
                 yes_no(exists) ? " (or -1: driven)" : "");
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
     * specs, is valid and drives its load; the row holds no power_out, so 1 and
     * TOL_GOOD_DRIVEN (not good for that alone, never with allow_driven) are
     * the two values where the outputs allow it, 0 the one where they do not */
    const int allows = tol_row_allows_good(t, row);
    if ((good != 0.0) != allows || (good == TOL_GOOD_DRIVEN && t->opt.allow_driven)) {
        snprintf(why, USM_MSG_LEN, "sample %llu: good is %g but its outputs say %s",
                 (unsigned long long)i, good,
                 !allows ? "0" : t->opt.allow_driven ? "1" : "1 (or -1: driven)");
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

/* The checkpoint file of rank r: FILE for rank 0 (the serial run's), FILE.r
 * for the others. */
static void part_path(const usm_tolerance *t, int r, char *buf, size_t len)
{
    if (r == 0)
        snprintf(buf, len, "%s", t->opt.checkpoint);
    else
        snprintf(buf, len, "%s.%d", t->opt.checkpoint, r);
}

static int refuse_path(usm_tolerance *t, const char *path, const char *why)
{
    snprintf(t->msg, USM_MSG_LEN, "checkpoint %.60s: %.180s", path, why);
    return USM_EINPUT;
}

/* fread of n bytes that continues the CRC-32 of what was read. */
static int read_crc(void *buf, size_t n, FILE *f, uLong *crc)
{
    if (fread(buf, 1, n, f) != n)
        return -1;
    *crc = crc32(*crc, buf, (uInt)n);
    return 0;
}

/* A line of at most len - 1 bytes, continuing the CRC. */
static int line_crc(char *line, int len, FILE *f, uLong *crc)
{
    if (!fgets(line, len, f))
        return -1;
    *crc = crc32(*crc, (const Bytef *)line, (uInt)strlen(line));
    return 0;
}

/* Whether the rest of f (after the bytes whose CRC-32 is crc) ends with the
 * CRC-32 of all of it but its last 16 bytes (the stored CRC and ORDER). */
static int crc_matches(FILE *f, uLong crc)
{
    unsigned char buf[1 << 16], keep[16];
    size_t held = 0, got;
    while ((got = fread(buf, 1, sizeof buf, f)) > 0) {
        /* the 16 bytes held back are not the last ones: into the CRC */
        const size_t all = held + got, out = all > 16 ? all - 16 : 0;
        unsigned char joined[16 + sizeof buf];
        memcpy(joined, keep, held);
        memcpy(joined + held, buf, got);
        crc = crc32(crc, joined, (uInt)out);
        held = all - out;
        memcpy(keep, joined + out, held);
    }
    uint64_t stored;
    if (held != 16)
        return 0;
    memcpy(&stored, keep, sizeof stored);
    return stored == (uint64_t)crc;
}

/* The header of checkpoint file `path` (file k of the set): magic, the
 * library version, "part R of S", the configuration.  USM_OK with the file
 * at its binary part and *parts = S; *missing = 1 (and USM_OK) when there is
 * no such file; else a refusal. */
static int read_header(usm_tolerance *t, const char *path, int k, FILE **fp, uLong *crc,
                       int *parts, int *missing)
{
    char line[512], why[USM_MSG_LEN];
    const size_t clen = strlen(t->config);
    size_t have = 0;
    char *text;
    int ended = 0, r = -1, s = 0, status = USM_OK;
    struct stat st;
    /* O_NONBLOCK: a pipe at path must be refused, not hang the run in open */
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0 && fstat(fd, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
        close(fd);
        return refuse_path(t, path, "not a regular file (a pipe, device or socket); "
                                    "usm reads and writes a checkpoint as a file");
    }
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (fd >= 0 && !f)
        close(fd);
    *missing = 0;
    *fp = NULL;
    if (!f) {
        if (errno != ENOENT) {
            snprintf(t->msg, USM_MSG_LEN, "checkpoint %.120s: %s", path, strerror(errno));
            return USM_EINPUT;
        }
        *missing = 1;
        return USM_OK;
    }
    if (!fgets(line, sizeof line, f) || strncmp(line, "usm tolerance checkpoint ", 25) != 0) {
        fclose(f);
        return refuse_path(t, path, "not a usm tolerance checkpoint (refusing to overwrite it)");
    }
    if (strcmp(line, MAGIC) != 0) {
        fclose(f);
        snprintf(why, sizeof why, "written in another format (\"%.40s\"; this usm %s writes "
                 "format 3, with its version and a checksum): a checkpoint is resumed by the "
                 "usm that wrote it; remove it", strtok(line, "\n"), usm_version());
        return refuse_path(t, path, why);
    }
    *crc = crc32(0L, Z_NULL, 0);
    if (line_crc(line, sizeof line, f, crc) != 0 || strncmp(line, "usm ", 4) != 0) {
        fclose(f);
        return refuse_path(t, path, "damaged: no library version line");
    }
    line[strcspn(line, "\n")] = '\0';
    if (strcmp(line + 4, usm_version()) != 0) {
        fclose(f);
        snprintf(why, sizeof why, "written by usm %.40s, this is usm %s: a checkpoint is "
                 "resumed by the same version only (another build may compute other bits); "
                 "remove it", line + 4, usm_version());
        return refuse_path(t, path, why);
    }
    if (line_crc(line, sizeof line, f, crc) != 0 || sscanf(line, "part %d of %d", &r, &s) != 2 ||
        r != k || s < 1 || r >= s) {
        fclose(f);
        snprintf(why, sizeof why, "damaged: its part line is not \"part %d of S\"", k);
        return refuse_path(t, path, why);
    }
    if (!(text = malloc(clen + 1))) {
        fclose(f);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    text[0] = '\0';
    /* the configuration, up to "end" */
    while (line_crc(line, sizeof line, f, crc) == 0 && !(ended = strcmp(line, "end\n") == 0)) {
        const size_t l = strlen(line);
        if (have + l > clen) {
            have = clen + 1; /* longer than this study's: differs */
            break;
        }
        memcpy(text + have, line, l + 1);
        have += l;
    }
    if (!ended && have <= clen) {
        status = refuse_path(t, path, "truncated (in its configuration)");
    } else if (have != clen || memcmp(text, t->config, clen) != 0) {
        char a[80], b[80];
        if (have > clen)
            snprintf(a, sizeof a, "a longer configuration"), snprintf(b, sizeof b, "%s", "");
        else
            first_difference(text, t->config, a, b);
        /* a byte damaged in the configuration is not another study */
        if (!crc_matches(f, *crc))
            snprintf(why, sizeof why, "damaged: its CRC-32 does not match its bytes (its "
                     "configuration reads \"%.70s\" where this run has \"%.70s\")", a, b);
        else
            snprintf(why, sizeof why, "written by another study (it has \"%.70s\" where this "
                     "run has \"%.70s\"); use another file or remove it", a, b);
        status = refuse_path(t, path, why);
    }
    free(text);
    if (status != USM_OK) {
        fclose(f);
        return status;
    }
    *fp = f;
    *parts = s;
    return USM_OK;
}

/* The blocks of an open checkpoint file (after its header): those this rank
 * owns into t->rows (checked row by row), the others read past; the CRC-32
 * of the whole file after its first line must match the one stored.  USM_OK
 * or a refusal (the blocks read are then not marked done). */
static int read_blocks(usm_tolerance *t, const char *path, FILE *f, uLong crc, uint64_t *got)
{
    uint64_t order = 0, n = 0, stored = 0;
    int status = USM_OK;
    char why[USM_MSG_LEN];
    double *skip = malloc(USM_TOLERANCE_BLOCK * (size_t)t->width * sizeof *skip);
    uint64_t *mine = malloc((t->bhi - t->blo + 1) * sizeof *mine), nmine = 0;
    if (!skip || !mine) {
        free(skip);
        free(mine);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    if (read_crc(&order, sizeof order, f, &crc) != 0 || order != ORDER ||
        read_crc(&n, sizeof n, f, &crc) != 0) {
        status = refuse_path(t, path, "truncated or from a host of another byte order");
    } else if (n > t->nblocks) {
        snprintf(why, sizeof why, "damaged: %llu blocks stored, the study has %llu",
                 (unsigned long long)n, (unsigned long long)t->nblocks);
        status = refuse_path(t, path, why);
    }
    for (uint64_t k = 0; status == USM_OK && k < n; ++k) {
        uint64_t b;
        if (read_crc(&b, sizeof b, f, &crc) != 0) {
            status = refuse_path(t, path, "truncated");
            break;
        }
        if (b >= t->nblocks) {
            snprintf(why, sizeof why, "damaged: block index %llu beyond the study",
                     (unsigned long long)b);
            status = refuse_path(t, path, why);
            break;
        }
        const int own = b >= t->blo && b < t->bhi && !t->done[b];
        const uint64_t rows_n = tol_block_size(t, b);
        const size_t cnt = (size_t)(rows_n * (uint64_t)t->width);
        double *rows = own ? tol_block_rows(t, b) : skip;
        if (read_crc(rows, cnt * sizeof(double), f, &crc) != 0) {
            status = refuse_path(t, path, "truncated");
            break;
        }
        for (uint64_t i = 0; own && i < rows_n; ++i) {
            const char *bad = check_row(t, b * USM_TOLERANCE_BLOCK + i,
                                        rows + i * (uint64_t)t->width, why);
            if (bad) {
                char w2[USM_MSG_LEN];
                snprintf(w2, sizeof w2, "damaged: %.200s", bad);
                status = refuse_path(t, path, w2);
                break;
            }
        }
        if (own && status == USM_OK) {
            t->done[b] = 1;
            mine[nmine++] = b;
        }
    }
    const uLong want = crc;
    if (status == USM_OK && (fread(&stored, sizeof stored, 1, f) != 1 ||
                             fread(&order, sizeof order, 1, f) != 1 || order != ORDER))
        status = refuse_path(t, path, "truncated");
    else if (status == USM_OK && stored != (uint64_t)want) {
        snprintf(why, sizeof why, "damaged: its CRC-32 is %08llx, its bytes give %08lx",
                 (unsigned long long)stored, want);
        status = refuse_path(t, path, why);
    } else if (status == USM_OK && fgetc(f) != EOF)
        status = refuse_path(t, path, "damaged: data after the end");
    if (status != USM_OK)
        for (uint64_t k = 0; k < nmine; ++k)
            t->done[mine[k]] = 0;
    *got = status == USM_OK ? nmine : 0;
    free(skip);
    free(mine);
    return status;
}

int tol_checkpoint_load(usm_tolerance *t)
{
    char path[USM_OUTFILE_PATH + 16], why[USM_MSG_LEN];
    int limit = t->size, status = USM_OK;
    uint64_t resumed = 0;
    /* this rank's own file must be writable later (or refused now) */
    part_path(t, t->rank, path, sizeof path);
    {
        struct stat st;
        if (lstat(path, &st) != 0) {
            if (errno != ENOENT) {
                snprintf(t->msg, USM_MSG_LEN, "checkpoint %.120s: %s", path, strerror(errno));
                return USM_EINPUT;
            }
            if (usm_outfile_check(path, 1, why, sizeof why) != USM_OK) {
                snprintf(t->msg, USM_MSG_LEN, "checkpoint %.200s", why);
                return USM_EINPUT;
            }
        } else if (stat(path, &st) != 0) {
            return refuse_path(t, path, "a symbolic link to nothing; refusing to write through it");
        }
    }
    /* the files of the set (FILE's header says how many a run wrote): each one
     * whose blocks overlap this rank's is read */
    for (int k = 0; k < limit && status == USM_OK; ++k) {
        FILE *f;
        uLong crc;
        int parts, missing;
        uint64_t lo, hi, got = 0;
        part_path(t, k, path, sizeof path);
        status = read_header(t, path, k, &f, &crc, &parts, &missing);
        if (status != USM_OK || missing)
            continue;
        if (k == 0 && parts > limit)
            limit = parts;
        tol_owned(t->nblocks, k, parts, &lo, &hi);
        if (lo < t->bhi && t->blo < hi)
            status = read_blocks(t, path, f, crc, &got);
        resumed += got;
        fclose(f);
    }
    if (status != USM_OK) {
        memset(t->done, 0, t->nblocks);
        return status;
    }
    t->sum.resumed_blocks = resumed;
    return USM_OK;
}

int tol_checkpoint_write(usm_tolerance *t)
{
    char path[USM_OUTFILE_PATH], tmp[USM_OUTFILE_PATH], why[USM_MSG_LEN], head[64];
    uint64_t n = 0;
    FILE *f;
    int bad, fd, status;
    const double start = tol_now();
    part_path(t, t->rank, path, sizeof path);
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
    for (uint64_t b = t->blo; b < t->bhi; ++b)
        n += t->done[b];
    uLong crc = crc32(0L, Z_NULL, 0);
    const int hl = snprintf(head, sizeof head, "usm %s\npart %d of %d\n", usm_version(), t->rank,
                            t->size);
    crc = crc32(crc, (const Bytef *)head, (uInt)hl);
    crc = crc32(crc, (const Bytef *)t->config, (uInt)strlen(t->config));
    crc = crc32(crc, (const Bytef *)"end\n", 4);
    crc = crc32(crc, (const Bytef *)&ORDER, sizeof ORDER);
    crc = crc32(crc, (const Bytef *)&n, sizeof n);
    bad = fputs(MAGIC, f) < 0 || fputs(head, f) < 0 || fputs(t->config, f) < 0 ||
          fputs("end\n", f) < 0 || fwrite(&ORDER, sizeof ORDER, 1, f) != 1 ||
          fwrite(&n, sizeof n, 1, f) != 1;
    for (uint64_t b = t->blo; !bad && b < t->bhi; ++b) {
        if (!t->done[b])
            continue;
        const size_t cnt = (size_t)(tol_block_size(t, b) * (uint64_t)t->width);
        const double *rows = tol_block_rows(t, b);
        bad = fwrite(&b, sizeof b, 1, f) != 1 || fwrite(rows, sizeof(double), cnt, f) != cnt;
        crc = crc32(crc32(crc, (const Bytef *)&b, sizeof b), (const Bytef *)rows,
                    (uInt)(cnt * sizeof(double)));
    }
    const uint64_t stored = crc;
    bad = bad || fwrite(&stored, sizeof stored, 1, f) != 1 ||
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

const char *tol_checkpoint_path(const usm_tolerance *t, char *buf, size_t len)
{
    part_path(t, t->rank, buf, len);
    return buf;
}

int tol_checkpoint_open(usm_tolerance *t)
{
    if (!t->opt.checkpoint)
        return USM_OK;
    /* one run per checkpoint: a second one fails at once, not at a rename */
    int status = tol_checkpoint_load(t), input;
    char why[USM_MSG_LEN], own[USM_OUTFILE_PATH + 16];
    if (status == USM_OK &&
        (t->lock_fd = usm_outfile_lock(tol_checkpoint_path(t, own, sizeof own), why,
                                       sizeof why, &input)) < 0) {
        snprintf(t->msg, USM_MSG_LEN, "checkpoint %.200s", why);
        status = input ? USM_EINPUT : USM_EFAILED;
    }
    return status;
}
