/* The checkpoint file of a tolerance study (usm_tolerance.h).
 *
 * Layout: the text line MAGIC, the study's configuration (tolerance.c,
 * build_config: one "key value" line each, numbers exact in %a), the line
 * "end", then binary in the host's byte order: ORDER (a uint64 that reads
 * back only on a host of the same byte order), the number of blocks stored,
 * each block as its index (uint64) and its rows (doubles, bit for bit), and
 * ORDER again (a truncated file is refused, not half read).  It is written to
 * a temporary beside FILE (core/outfile.c: a fresh name, created with
 * O_EXCL|O_NOFOLLOW, so never through a symlink) and renamed over FILE, so
 * FILE is always one complete write and a symlink is replaced, never
 * written through. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sys/stat.h>

#include "core/outfile.h"
#include "tolerance_io.h"

static const char MAGIC[] = "usm tolerance checkpoint 1\n";
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
    if (!fgets(line, sizeof line, f) || strcmp(line, MAGIC) != 0) {
        fclose(f);
        return refuse(t, "not a usm tolerance checkpoint (refusing to overwrite it)");
    }
    if (!(text = malloc(clen + 1))) {
        fclose(f);
        snprintf(t->msg, USM_MSG_LEN, "out of memory");
        return USM_EFAILED;
    }
    text[0] = '\0';
    /* the configuration, up to "end" */
    while (fgets(line, sizeof line, f) && strcmp(line, "end\n") != 0) {
        const size_t l = strlen(line);
        if (have + l > clen) {
            have = clen + 1; /* longer than this study's: differs */
            break;
        }
        memcpy(text + have, line, l + 1);
        have += l;
    }
    if (have != clen || memcmp(text, t->config, clen) != 0) {
        char a[80], b[80], why[USM_MSG_LEN];
        if (have > clen)
            snprintf(a, sizeof a, "a longer configuration"), snprintf(b, sizeof b, "%s", "");
        else
            first_difference(text, t->config, a, b);
        snprintf(why, sizeof why, "written by another study (it has \"%.70s\" where this run "
                 "has \"%.70s\"); use another file or remove it", a, b);
        status = refuse(t, why);
    } else if (fread(&order, sizeof order, 1, f) != 1 || order != ORDER ||
               fread(&n, sizeof n, 1, f) != 1 || n > t->nblocks) {
        status = refuse(t, "truncated or from a host of another byte order");
    }
    for (uint64_t k = 0; status == USM_OK && k < n; ++k) {
        uint64_t b;
        if (fread(&b, sizeof b, 1, f) != 1 || b >= t->nblocks || t->done[b]) {
            status = refuse(t, "corrupt block index");
            break;
        }
        const size_t cnt = (size_t)(tol_block_size(t, b) * (uint64_t)t->width);
        if (fread(t->rows + b * USM_TOLERANCE_BLOCK * (uint64_t)t->width, sizeof(double), cnt,
                  f) != cnt) {
            status = refuse(t, "truncated");
            break;
        }
        t->done[b] = 1;
    }
    if (status == USM_OK && (fread(&order, sizeof order, 1, f) != 1 || order != ORDER))
        status = refuse(t, "truncated");
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
    for (uint64_t b = 0; !bad && b < t->nblocks; ++b) {
        if (!t->done[b])
            continue;
        const size_t cnt = (size_t)(tol_block_size(t, b) * (uint64_t)t->width);
        bad = fwrite(&b, sizeof b, 1, f) != 1 ||
              fwrite(t->rows + b * USM_TOLERANCE_BLOCK * (uint64_t)t->width, sizeof(double),
                     cnt, f) != cnt;
    }
    bad = bad || fwrite(&ORDER, sizeof ORDER, 1, f) != 1 || fflush(f) != 0 ||
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
