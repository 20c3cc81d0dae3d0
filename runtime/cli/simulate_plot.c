/* gnuplot plots of a `usm simulate` time history (see simulate_plot.h). */
#define _POSIX_C_SOURCE 200809L
#include "simulate_plot.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "usm.h"

extern char **environ;

static const char *const headers[CLI_NCOLS] = {
    "t [s]",          "phi [rad]",      "theta [rad]",   "psi [rad]",
    "phidot [rad/s]", "thetadot [rad/s]", "psidot [rad/s]", "phi_R [rad]",
    "phi_Rdot [rad/s]", "F_n [N]",      "F_t [N]",       "v_rel [m/s]",
    "theta_avg [rad]", "phi_Rdot_avg [rad/s]"};

const char *cli_sim_column_header(int c)
{
    return c >= 1 && c <= CLI_NCOLS ? headers[c - 1] : "";
}

static const char *const suffixes[] = {".gp", ".png", ".svg"};

static void path_of(char *buf, size_t len, const char *prefix, const char *suffix)
{
    snprintf(buf, len, "%s%s", prefix, suffix);
}

int cli_plot_check(const char *prefix, int force, char msg[CLI_MSG_LEN])
{
    char path[4096];
    struct stat st;
    if (prefix[0] == '\0') {
        cli_msg(msg, "--plot: empty prefix");
        return USM_EINPUT;
    }
    if (strlen(prefix) + 5 > sizeof path) {
        cli_msg(msg, "--plot: prefix is too long");
        return USM_EINPUT;
    }
    for (size_t k = 0; k < sizeof suffixes / sizeof suffixes[0]; ++k) {
        path_of(path, sizeof path, prefix, suffixes[k]);
        if (!force && stat(path, &st) == 0) {
            cli_msg(msg, "--plot %s: exists; refusing to overwrite it (use --force)", path);
            return USM_EINPUT;
        }
    }
    return USM_OK;
}

/* A gnuplot single-quoted string: '' stands for one quote, nothing else is
 * special inside. */
static void quoted(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; *s; ++s) {
        if (*s == '\'')
            fputc('\'', f);
        fputc(*s, f);
    }
    fputc('\'', f);
}

static void panel(FILE *f, const cli_plot_spec *sp, const char *ylabel, int col, const char *name,
                  int avg_col, const char *avg_name, int have_ref, double ref,
                  const char *ref_name)
{
    fprintf(f, "  set ylabel '%s'\n", ylabel);
    fprintf(f, "  plot csv using ($1*1e3):%d every stride with lines lc rgb '#9ab8d8' title '%s'",
            col, name);
    if (avg_col > 0)
        fprintf(f, ", \\\n       csv using ($1*1e3):%d with lines lw 2 lc rgb '#08306b' title '%s'",
                avg_col, avg_name);
    if (have_ref)
        fprintf(f, ", \\\n       %.17g with lines dt 2 lw 2 lc rgb '#d62728' title '%s'", ref,
                ref_name);
    (void)sp;
    fprintf(f, "\n");
}

int cli_plot_write(const cli_plot_spec *sp, int force, char msg[CLI_MSG_LEN])
{
    char path[4096];
    int fd;
    FILE *f;
    path_of(path, sizeof path, sp->prefix, ".gp");
    fd = open(path, O_WRONLY | O_CREAT | (force ? O_TRUNC : O_EXCL), 0666);
    if (fd < 0 || !(f = fdopen(fd, "w"))) {
        cli_msg(msg, "--plot %s: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd);
        return USM_EFAILED;
    }
    fprintf(f, "# Start-up plots of a `usm simulate` run; regenerate with: gnuplot ");
    quoted(f, path);
    fprintf(f, "\n# Thin lines: sampled values (aliased if the sampling rate is below about\n"
               "# 10 f); thick lines: means over one excitation period; dashed: the\n"
               "# stationary solution.\n");
    fprintf(f, "csv = ");
    quoted(f, sp->csv);
    fprintf(f, "\nset datafile separator ','\n");
    /* every point of an SVG is an element: keep the files reasonable */
    fprintf(f, "stats csv using 1 nooutput\nstride = STATS_records > 20000 ? "
               "int(ceil(STATS_records / 20000.0)) : 1\n");
    fprintf(f, "set grid\nset key top right\nset xlabel 't [ms]'\n");
    if (sp->settled)
        fprintf(f,
                "set arrow 1 from %.17g, graph 0 to %.17g, graph 1 nohead dt 2 lw 2 lc rgb '#2ca02c'\n"
                "set label 1 'settled' at %.17g, graph 0.92 offset 0.5, 0 tc rgb '#2ca02c'\n",
                sp->t_settle * 1e3, sp->t_settle * 1e3, sp->t_settle * 1e3);
    fprintf(f, "do for [fmt in 'png svg'] {\n"
               "  if (fmt eq 'png') {\n"
               "    if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
               "      set terminal pngcairo size 1000,1100 noenhanced\n"
               "    } else {\n"
               "      set terminal png size 1000,1100 noenhanced\n"
               "    }\n"
               "    set output ");
    path_of(path, sizeof path, sp->prefix, ".png");
    quoted(f, path);
    fprintf(f, "\n  } else {\n    set terminal svg size 1000,1100 noenhanced\n    set output ");
    path_of(path, sizeof path, sp->prefix, ".svg");
    quoted(f, path);
    fprintf(f, "\n  }\n  set multiplot layout 3,1 title ");
    quoted(f, sp->title);
    fprintf(f, "\n");
    panel(f, sp, "tilt theta [rad]", CLI_COL_THETA, "theta", CLI_COL_THETA_AVG,
          "mean over one period", sp->have_steady, sp->theta_bar, "stationary");
    panel(f, sp, "rotor speed phi_Rdot [1/s]", CLI_COL_PHI_RDOT, "phi_Rdot", CLI_COL_PHI_RDOT_AVG,
          "mean over one period", sp->have_steady, sp->speed_bar, "stationary");
    fprintf(f, "  set ylabel 'contact force [N]'\n"
               "  plot csv using ($1*1e3):%d every stride with lines lc rgb '#1f77b4' title 'F_n', \\\n"
               "       csv using ($1*1e3):%d every stride with lines lc rgb '#ff7f0e' title 'F_t'",
            CLI_COL_F_N, CLI_COL_F_T);
    if (sp->stick)
        fprintf(f, ", \\\n       csv using ($1*1e3):(%.17g*$%d) every stride with lines dt 2 "
                   "lc rgb '#7f7f7f' title 'mu0 F_n (stick limit)'",
                sp->mu0, CLI_COL_F_N);
    fprintf(f, ", \\\n       0 with lines lc rgb 'black' notitle\n"
               "  unset multiplot\n"
               "  set output\n"
               "}\n");
    if (fflush(f) != 0 || ferror(f)) {
        fclose(f);
        cli_msg(msg, "--plot %s.gp: write error", sp->prefix);
        return USM_EFAILED;
    }
    if (fclose(f) != 0) {
        cli_msg(msg, "--plot %s.gp: write error", sp->prefix);
        return USM_EFAILED;
    }
    return USM_OK;
}

int cli_plot_run(const char *prefix, char msg[CLI_MSG_LEN])
{
    char path[4096];
    char prog[] = "gnuplot";
    char *argv[3] = {prog, path, NULL};
    pid_t pid;
    int status, rc;
    path_of(path, sizeof path, prefix, ".gp");
    /* stdout of the command may carry the summary: gnuplot's chatter goes to stderr */
    fflush(stdout);
    fflush(stderr);
    rc = posix_spawnp(&pid, prog, NULL, NULL, argv, environ);
    if (rc == ENOENT) {
        cli_msg(msg, "--plot: gnuplot is not installed; the script is %s", path);
        return USM_ENOSOLUTION;
    }
    if (rc != 0) {
        cli_msg(msg, "--plot: cannot run gnuplot: %s", strerror(rc));
        return USM_EFAILED;
    }
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            cli_msg(msg, "--plot: waiting for gnuplot: %s", strerror(errno));
            return USM_EFAILED;
        }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
            cli_msg(msg, "--plot: gnuplot is not installed; the script is %s", path);
        else
            cli_msg(msg, "--plot: gnuplot failed on %s", path);
        return WIFEXITED(status) && WEXITSTATUS(status) == 127 ? USM_ENOSOLUTION : USM_EFAILED;
    }
    return USM_OK;
}
