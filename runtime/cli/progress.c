/* The one progress line of the usm command (progress.h). */
#define _POSIX_C_SOURCE 200809L
#include "progress.h"

#include <math.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* 49 s, 12 min 5 s, 3 h 02 min: as precise as a wait is worth. */
static void duration(char *buf, size_t len, double s)
{
    if (!(s < 1e8))
        snprintf(buf, len, "?");
    else if (s < 60)
        snprintf(buf, len, "%.0f s", s);
    else if (s < 3600)
        snprintf(buf, len, "%d min %02d s", (int)(s / 60), (int)s % 60);
    else
        snprintf(buf, len, "%d h %02d min", (int)(s / 3600), (int)(s / 60) % 60);
}

static void draw(void *ctx, long done, long total, const char *what)
{
    cli_progress *p = ctx;
    const double now = mono();
    char line[256], left[64] = "", rate[64] = "";
    if (p->first) {
        p->first = 0;
        p->done0 = done;
        p->t0 = now;
    }
    const double dt = now - p->t0, per_s = dt > 0 ? (double)(done - p->done0) / dt : 0.0;
    if (per_s > 0) {
        snprintf(rate, sizeof rate, per_s >= 100 ? "  %.0f/s" : "  %.3g/s", per_s);
        if (done < total) {
            char d[48];
            duration(d, sizeof d, (double)(total - done) / per_s);
            snprintf(left, sizeof left, "  %s left", d);
        }
    }
    int n = snprintf(line, sizeof line, "%s: %ld/%ld %s (%.0f%%)%s%s", p->name, done, total,
                     what ? what : "", total > 0 ? 100.0 * (double)done / (double)total : 100.0,
                     rate, left);
    if (n < 0)
        return;
    if (n >= (int)sizeof line)
        n = (int)sizeof line - 1;
    /* pad over what is left of a longer previous line */
    fprintf(stderr, "\r%s%*s", line, p->width > n ? p->width - n : 0, "");
    fflush(stderr);
    p->width = n;
}

void cli_progress_init(cli_progress *p, const char *name, int quiet)
{
    memset(p, 0, sizeof *p);
    p->name = name;
    p->on = !quiet && isatty(STDERR_FILENO);
    p->first = 1;
}

usm_progress cli_progress_callback(cli_progress *p)
{
    usm_progress cb = {p->on ? draw : NULL, p};
    return cb;
}

void cli_progress_fraction(double fraction, void *ctx)
{
    cli_progress *p = ctx;
    const long done = lround(fraction * (double)p->total);
    const double now = mono();
    if (!p->on || (!p->first && done < p->total && now - p->last < 0.1))
        return;
    p->last = now;
    draw(p, done, p->total, p->what);
}

void cli_progress_end(cli_progress *p)
{
    if (p->width > 0) {
        fprintf(stderr, "\r%*s\r", p->width, "");
        fflush(stderr);
    }
    p->width = 0;
}

int cli_quiet_option(int *quiet, int argc, char **argv, int *i)
{
    (void)argc;
    if (strcmp(argv[*i], "--quiet") != 0)
        return CLI_OPT_NOT_MINE;
    *quiet = 1;
    return CLI_OPT_TAKEN;
}

void cli_quiet_usage(FILE *out)
{
    fprintf(out, "  --quiet             no progress line (drawn on stderr only when it is a "
                 "terminal)\n");
}
