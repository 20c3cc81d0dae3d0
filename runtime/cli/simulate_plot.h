/* simulate_plot.h: the CSV layout of `usm simulate` and its gnuplot plots.
 *
 * Plotting is kept out of the integrator: it reads only the CSV file and a
 * few numbers of the summary, writes a gnuplot script PREFIX.gp and runs
 * gnuplot on it, which writes PREFIX.png and PREFIX.svg.
 */
#ifndef USM_CLI_SIMULATE_PLOT_H
#define USM_CLI_SIMULATE_PLOT_H

#include "diag.h"

/* Columns of the time-history CSV, numbered from 1 as gnuplot does. */
enum {
    CLI_COL_T = 1,
    CLI_COL_PHI,
    CLI_COL_THETA,
    CLI_COL_PSI,
    CLI_COL_PHIDOT,
    CLI_COL_THETADOT,
    CLI_COL_PSIDOT,
    CLI_COL_PHI_R,
    CLI_COL_PHI_RDOT,
    CLI_COL_F_N,
    CLI_COL_F_T,
    CLI_COL_V_REL,
    CLI_COL_THETA_AVG,
    CLI_COL_PHI_RDOT_AVG,
    CLI_NCOLS = CLI_COL_PHI_RDOT_AVG
};

/* Header of column c (1-based): "name [unit]". */
const char *cli_sim_column_header(int c);

typedef struct cli_plot_spec {
    const char *csv;      /* the time history */
    const char *prefix;   /* PREFIX.gp, PREFIX.png, PREFIX.svg */
    const char *title;    /* first line of the plot title */
    int stick;            /* stick model: draw mu0 F_n */
    double mu0;
    int have_steady;
    double theta_bar, speed_bar; /* stationary tilt [rad] and rotor speed [1/s] */
    int settled;
    double t_settle;      /* [s] */
} cli_plot_spec;

/* USM_OK when none of PREFIX.gp/.png/.svg exists (or force); USM_EINPUT
 * with "--plot FILE: exists..." otherwise. */
int cli_plot_check(const char *prefix, int force, char msg[CLI_MSG_LEN]);

/* Write PREFIX.gp.  USM_OK, or USM_EFAILED with a message. */
int cli_plot_write(const cli_plot_spec *spec, int force, char msg[CLI_MSG_LEN]);

/* Run gnuplot on PREFIX.gp (no shell).  USM_OK; USM_ENOSOLUTION when gnuplot
 * is not installed (msg says so); USM_EFAILED when it failed. */
int cli_plot_run(const char *prefix, char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_SIMULATE_PLOT_H */
