/* usm_io.h: reading and writing the files of the usm command, for any
 * program: parameter files, numbers as users type them, a simulation's start
 * state, and the outputs of `usm steady` and `usm sweep` (the same keys,
 * columns and digits as the command; formats in docs/cli.md and docs/sweep.md).
 *
 * CSV dialect (sweep, map, simulate, report): one header line, a column with
 * a unit named "NAME [UNIT]"; numbers as the shortest text that reads back
 * exactly; an empty field where a value does not exist.  JSON numbers too are
 * the shortest text that reads back bit for bit (0.005, not
 * 0.0050000000000000001); a non-finite value is null.
 *
 * Messages name the file (or field) and the reason; they get USM_IO_MSG_LEN
 * bytes, room for a path.
 *
 * Thread safety: no global mutable state; every function may be called from
 * several threads at once on distinct arguments.
 */
#ifndef USM_IO_H
#define USM_IO_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"
#include "usm_design.h"
#include "usm_fit.h"
#include "usm_operating_point.h"
#include "usm_simulate.h"
#include "usm_sweep.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Length of the message buffers of this header. */
#define USM_IO_MSG_LEN 1024

/* ---- files ------------------------------------------------------------------ */

/* Length of a path held by usm_io_file. */
#define USM_IO_PATH_LEN 4096

/* An output file that appears whole or not at all.  usm_io_create opens a
 * temporary beside path (DIR/.BASE.usm-PID-XXXXXX.part, created with
 * O_CREAT|O_EXCL|O_NOFOLLOW: never through a symlink); usm_io_commit renames
 * it to path once everything is written, usm_io_abort removes it.  A reader
 * sees the old file, the new one, or none -- never a partial file under
 * path.  Without force nothing that exists at path is replaced: neither a
 * file nor a symlink (dangling or not); the final step is link(2), which
 * cannot replace a name that appeared meanwhile.  With force, rename(2)
 * replaces the name path itself: a symlink there is replaced by the file,
 * its target is never written.  A pipe, device or socket at path is
 * refused, with force too (USM_EINPUT): usm never opens one for writing.
 * A killed run leaves at most a temporary; the next usm_io_create of the
 * same path removes those whose process is gone (its own user's regular
 * files only). */
typedef struct usm_io_file {
    FILE *f;                    /* write here */
    int force;
    char path[USM_IO_PATH_LEN]; /* the final name */
    char tmp[USM_IO_PATH_LEN];  /* the temporary ("" for a device) */
} usm_io_file;

/* USM_OK when a file can be written at path now (called before a
 * computation, so that it does not fail late): its directory exists and is
 * writable, path is not a directory, pipe, device or socket and, unless
 * force, nothing exists there (a file, or a symlink even dangling).  Else USM_EINPUT with
 * "PATH: reason" in msg. */
int usm_io_check(const char *path, int force, char msg[USM_IO_MSG_LEN]);

/* Open out->f on a temporary for path (the checks of usm_io_check first).
 * out->f, or NULL with "PATH: reason" in msg and *status USM_EINPUT (exists,
 * cannot be created) or USM_EFAILED.  Follow with usm_io_commit or
 * usm_io_abort. */
FILE *usm_io_create(usm_io_file *out, const char *path, int force, char msg[USM_IO_MSG_LEN],
                    int *status);

/* Close out->f and, when everything was written (no stream error), rename
 * the temporary to out->path.  USM_OK; else the temporary is removed and
 * msg says "PATH: write error" or "PATH: reason" with USM_EFAILED, or
 * USM_EINPUT when, without force, a file appeared at path meanwhile. */
int usm_io_commit(usm_io_file *out, char msg[USM_IO_MSG_LEN]);

/* Close out->f and remove the temporary: path keeps what it had.  A no-op
 * when out->f is NULL. */
void usm_io_abort(usm_io_file *out);

/* An output directory that appears whole or not at all (usm tolerance
 * --out DIR).  usm_io_dir_create makes a stage beside path,
 * PARENT/.NAME.usm-new-PID, when path does not exist or is an empty
 * directory: the files go there (out->work) and usm_io_dir_commit renames
 * the stage to path when all are written -- a reader sees no DIR or the
 * complete one.  With force and an existing, non-empty directory the files
 * are written into it (out->work is path; each file still whole through
 * usm_io_create).  A symlink at path is refused without force; with force
 * the link itself is replaced by the new directory (its target is never
 * written).  A stage left by a killed run is removed by the next
 * usm_io_dir_create of the same path once its process is gone: only its
 * regular files and symlinks (names, never followed), and only when it is
 * a real directory of this user's -- a symlink under a stage's name is
 * removed as a link, never entered. */
typedef struct usm_io_dir {
    char path[USM_IO_PATH_LEN];  /* the final directory */
    char stage[USM_IO_PATH_LEN]; /* the stage ("" when writing in place) */
    const char *work;            /* where to write: stage or path */
    int replace_link;            /* path was a symlink (force): the link is replaced */
} usm_io_dir;

/* USM_OK when a directory can be written at path now: it does not exist
 * (its parent a writable directory) or is an empty directory, or force and
 * a writable directory or a symlink (to be replaced); not a file.  Else USM_EINPUT
 * with "PATH: reason" in msg.  Called before the computation. */
int usm_io_dir_check(const char *path, int force, char msg[USM_IO_MSG_LEN]);

/* Prepare out for path (the checks of usm_io_dir_check, then the stage).
 * USM_OK, or USM_EINPUT / USM_EFAILED with msg. */
int usm_io_dir_create(usm_io_dir *out, const char *path, int force, char msg[USM_IO_MSG_LEN]);

/* The stage renamed to out->path (nothing to do in place).  USM_OK, or
 * USM_EINPUT with msg when path appeared meanwhile (not empty), or
 * USM_EFAILED; the stage is removed on failure. */
int usm_io_dir_commit(usm_io_dir *out, char msg[USM_IO_MSG_LEN]);

/* Remove the stage and its files (nothing in place). */
void usm_io_dir_abort(usm_io_dir *out);

/* USM_OK when the n files paths[k] one run writes (each named by the option
 * options[k], for the message) are n distinct files; else USM_EINPUT with
 * "OPTION_A A and OPTION_B B are the same file", refused before anything is
 * computed or written -- one output would replace the other.  The same
 * file: the same last component in the same directory, directories
 * compared by device and inode when they exist ("a.csv", "./a.csv" and
 * "d/../a.csv" are one). */
int usm_io_check_distinct(const char *const *paths, const char *const *options, int n,
                          char msg[USM_IO_MSG_LEN]);

/* A message about a file written in out->work named by the user's path:
 * every occurrence of the hidden stage in msg becomes out->path ("DIR/
 * samples.csv: No space left on device", not ".DIR.usm-new-PID/..."). */
void usm_io_dir_msg(const usm_io_dir *out, char msg[USM_IO_MSG_LEN]);

/* ---- numbers and parameter files ------------------------------------------- */

/* The text the CSV files write for a double: the first %.{P}g, P = 6 ... 17,
 * that reads back as exactly v ("0.005", "1e+06", "-12.345678901234567"),
 * computed with one print and one or two parses (runtime/io/csv_out.c).
 * Returns its length (< 32). */
int usm_format_shortest(char buf[32], double v);

/* Parse the `len` characters at `text` as a finite double (strtod syntax,
 * the whole text used, no blanks).  Rejected, with "FIELD: \"text\" reason"
 * in msg and USM_EINPUT: not a number, nan/inf, overflow (|x| > DBL_MAX) and
 * underflow: a nonzero text whose value is below the smallest normal double
 * (DBL_MIN, 2.2e-308), whether it would round to a subnormal or to 0 -- a
 * value that small is a typing mistake, and silently using 0 instead is a
 * wrong answer.  Integers of any size are read as doubles.  The command reads
 * --set values and parameter files with it. */
int usm_parse_number(const char *field, const char *text, size_t len, double *out,
                     char msg[USM_IO_MSG_LEN]);

/* Parse a value typed with an optional unit: "37.5kHz", "10deg", "0.5 mNm",
 * "400mN" (a blank may stand between number and unit; blanks inside the unit
 * are ignored; u, U+00B5 and U+03BC all mean micro).  `unit` is the SI unit
 * the value is wanted in, spelled as the contracts spell it
 * (usm_param_table[k].unit: "N m", "Hz", "rad", ...; also "s", "1/s", "W");
 * without a unit the number is taken in it.  The units accepted for each are
 * one table (usm_unit_at); a decimal number with a power-of-ten unit is scaled
 * in its exponent (400mN is the double nearest 0.4).  NULL unit: a plain
 * number, as usm_parse_number.  USM_EINPUT on a bad number (as
 * usm_parse_number) or an unknown unit, with "FIELD: \"text\": unknown unit
 * \"U\" for a value in [UNIT] (accepted: ...)" in msg. */
int usm_parse_quantity(const char *field, const char *unit, const char *text, size_t len,
                       double *out, char msg[USM_IO_MSG_LEN]);

/* The number of rows of the units table (for usm_unit_at). */
int usm_unit_count(void);

/* Row k (0 .. usm_unit_count() - 1) of the units table: the SI unit of its
 * dimension (`si`), the unit as typed (`name`) and its value in SI (`scale`;
 * any pointer may be NULL).  USM_EINPUT for a row out of range. */
int usm_unit_at(int k, const char **si, const char **name, double *scale);

/* ---- display units (--units) ------------------------------------------------- */

/* The units values are shown in, for people: tables, CSV files, event lines
 * and plot axes.  JSON stays SI.  One entry per dimension chosen; every other
 * dimension is shown in SI.  An all-zero usm_display shows everything in SI. */
#define USM_DISPLAY_MAX 8
typedef struct usm_display {
    int n;
    struct {
        const char *si;   /* the dimension's SI unit, as the contracts spell it */
        const char *name; /* the unit shown (a name of the units table) */
        double scale;     /* its value in SI: shown = SI value / scale */
    } unit[USM_DISPLAY_MAX];
} usm_display;

/* Parse a --units list: unit names of the units table, comma-separated
 * ("rpm,deg", "rpm, deg, kHz, mNm"), or "si".  Each name chooses how its
 * dimension is shown; a rotor speed chosen in rpm also shows rad/s columns in
 * rpm.  USM_EINPUT with "FIELD: reason" in msg for an unknown name, a
 * dimensionless unit (%: a ratio column is not one quantity) or two names of
 * one dimension. */
int usm_display_parse(const char *field, const char *spec, usm_display *d,
                      char msg[USM_IO_MSG_LEN]);

/* v, a value in SI unit `si`, as shown: the value in the chosen unit, and
 * that unit's name in *unit (si itself when d does not change it; d may be
 * NULL). */
double usm_display_value(const usm_display *d, const char *si, double v, const char **unit);

/* Copy a usm CSV text (len bytes: a header whose columns are "NAME [UNIT]",
 * rows, and comment lines "# TYPE at NAME = VALUE: ..." for events) to out
 * with every column of a chosen dimension converted: its header names the
 * unit shown, its numbers are scaled, an event's value follows its column.
 * Empty fields, text and other lines are copied as they are.  0, or -1 on a
 * write error. */
int usm_display_csv(const usm_display *d, const char *text, size_t len, FILE *out);

/* The units accepted for a value in SI unit `si`, ", "-separated, in buf
 * (truncated to len); returns how many there are (0: a number without
 * unit only). */
int usm_units_accepted(const char *si, char *buf, size_t len);

/* Set the parameters named in the parameter file at `path`, a JSON object
 * {"NAME": number, ...}, in *p (others keep their value).  A number is in
 * the parameter's SI unit; a string is a value with a unit ("f": "37.5 kHz",
 * usm_parse_quantity).  USM_OK, or USM_EINPUT with "PATH[:LINE:COLUMN]:
 * reason" in msg. */
int usm_params_read_file(const char *path, usm_params *p, char msg[USM_IO_MSG_LEN]);

/* The same on the `len` bytes at `text` (which need not end in NUL); `path`
 * names them in messages.  *p is changed only when the whole text is good.
 * Numbers go through usm_parse_number(), strings through usm_parse_quantity(). */
int usm_params_parse_text(const char *path, const char *text, size_t len, usm_params *p,
                          char msg[USM_IO_MSG_LEN]);

/* ---- measurements to fit (usm_fit.h) ------------------------------------------ */

/* Read the measurements of `usm fit --data FILE.csv` (docs/fit.md): a header
 * of "NAME [UNIT]" columns -- a parameter's name is a condition of each row
 * (f [kHz], T [mNm], F0 [N]), an output's name (usm_fit_output_find) a
 * measured value (speed [rpm], power_in [W]), sigma_OUTPUT its standard
 * deviation (for every measured output or for none) -- then one row per
 * measurement; blank lines and lines starting with # are skipped.  Units
 * are converted to SI through the units table.  An empty output field is a
 * value not measured in that row; an empty condition is refused.  USM_OK
 * with *out (usm_fit_data_free), or USM_EINPUT with one line
 * "PATH:LINE: column NAME: reason" in msg: an unknown column, a unit that
 * does not convert, a field that is not a finite number (nan), a condition
 * outside its parameter's range, a sigma that is not positive, a row with
 * another number of fields, a sigma column without its output. */
int usm_fit_data_read(const char *path, usm_fit_data **out, char msg[USM_IO_MSG_LEN]);
/* The same on the len bytes at text; path names them in messages. */
int usm_fit_data_parse_text(const char *path, const char *text, size_t len, usm_fit_data **out,
                            char msg[USM_IO_MSG_LEN]);

/* The `usm fit --json` object of result r (usm_fit_run) of model m on data d
 * from the parameters p, and a newline: estimates (estimate,
 * standard_error, ci95, start, scale, unit per fitted parameter),
 * correlation, chi2, dof, p_value (null when sigma_estimated),
 * sigma_estimated, sigma_scale, singular_values, identifiable,
 * unidentifiable [{"combination": {NAME: coefficient}, "singular_value",
 * "advice": {"output", "conditions", "score"} or null}], points (per
 * measured value: row, line, conditions, output, measured, model, sigma,
 * residual, flagged, reason).  0, or -1 on a write error or out of memory. */
int usm_fit_write_json(const usm_model *m, const usm_params *p, const usm_fit_data *d,
                       const usm_fit_result *r, FILE *out);
/* The table of `usm fit` for people, measured and model values in the
 * display units dsp (NULL: SI). */
void usm_fit_write_table(const usm_model *m, const usm_fit_data *d, const usm_fit_result *r,
                         const usm_display *dsp, FILE *out);
/* The residuals per measured value as CSV (`usm fit --out`): row, line, the
 * conditions [SI], output, unit, measured, model, sigma, residual, flagged
 * (0/1), reason ("" or why it is flagged).
 * 0, or -1 on a write error. */
int usm_fit_write_csv(const usm_fit_data *d, const usm_fit_result *r, FILE *out);

/* ---- a simulation's start state --------------------------------------------- */

/* Read the state of model m from the file at path into opt (x0, t0,
 * rotor_angle0): a CSV time history written by `usm simulate` (its last row)
 * or its JSON summary ("final_state").  USM_OK, or USM_EINPUT with
 * "PATH[:LINE]: reason" in msg. */
int usm_sim_read_start(const char *path, const usm_model *m, usm_sim_options *opt,
                       char msg[USM_IO_MSG_LEN]);

/* The time history's CSV header: t [s], phi theta psi [rad], phidot thetadot
 * psidot [rad/s], phi_R [rad], phi_Rdot [rad/s], F_n F_t [N], v_rel [m/s],
 * theta_avg [rad], phi_Rdot_avg [rad/s] (the last two: means over the last
 * complete excitation period, empty before the first). */
void usm_sim_csv_header(FILE *out);

/* One row of the time history (exact digits: usm_sim_read_start continues a
 * run from its last row).  0, or -1 on a write error. */
int usm_sim_csv_row(const usm_sim_sample *s, FILE *out);
/* The same header and rows with their values in the display units d
 * (--units; NULL: SI): a converted column names its unit ("phi_Rdot [rpm]"),
 * and usm_sim_read_start reads it back in SI. */
void usm_sim_csv_header_in(const usm_display *d, FILE *out);
/* One row of it (0, or -1 on a write error). */
int usm_sim_csv_row_in(const usm_sim_sample *s, const usm_display *d, FILE *out);

/* What `usm simulate` reports about a run. */
typedef struct usm_sim_report {
    const usm_model *model;
    const usm_params *params;
    const usm_sim_options *opt;
    const char *from_file;          /* where a FROM_STATE start came from, or NULL */
    const char *out;                /* the time history's file, or NULL */
    const usm_sim_summary *summary; /* of usm_sim_run */
    double wall;                    /* seconds the run took */
    /* --spectrum (usm_spectrum.h): the spectrum (NULL: none), its CSV file,
     * and why it was not computed (NULL or ""; with spectrum NULL and this
     * NULL or "", the summary has no spectrum keys) */
    const struct usm_sim_spectrum_result *spectrum;
    const char *spectrum_csv;
    const char *spectrum_error;
} usm_sim_report;

/* The summary as `usm simulate` prints it for people. */
void usm_sim_write_table(const usm_sim_report *r, FILE *out);
/* The same summary with tilts and speeds in the display units d (--units;
 * NULL: SI). */
void usm_sim_write_table_in(const usm_sim_report *r, const usm_display *d, FILE *out);

/* The summary as the `usm simulate --json` object and a newline (its
 * "final_state" is what usm_sim_read_start reads).  0, or -1 on a write error
 * or when out of memory. */
int usm_sim_write_json(const usm_sim_report *r, FILE *out);

/* ---- stationary solutions ----------------------------------------------------- */

/* What `usm steady` writes. */
typedef struct usm_steady_report {
    const usm_model *model;
    const usm_params *params;
    const usm_steady *steady;          /* its roots; 0 roots when error is set */
    const char *error;                 /* NULL when a root was found */
    const usm_floquet_result *floquet; /* of root 0, or NULL */
    const usm_floquet_result *roots_floquet; /* one per root (usm_floquet_roots), or NULL:
                                                then the roots carry no "floquet" */
    const usm_op_result *op;           /* the operating point (usm_operating_point), or
                                          NULL: no operating_point keys.  The top level
                                          describes root op->index when there is one
                                          (needs roots_floquet), else root 0 */
} usm_steady_report;

/* The `usm steady --json` object and a newline to out.  0, or -1 on a write
 * error or when out of memory. */
int usm_steady_write_json(const usm_steady_report *r, FILE *out);

/* The human-readable table of `usm steady` (only for a report without error). */
void usm_steady_table(const usm_steady_report *r, FILE *out);
/* The same table with its values in the display units d (--units; NULL: SI). */
void usm_steady_table_in(const usm_steady_report *r, const usm_display *d, FILE *out);

/* ---- sweeps -------------------------------------------------------------------- */

/* The sweep's CSV table: a header with units, one row per grid point, then the
 * events as comment lines starting with '#'.  `over` names the swept
 * parameter; floquet != 0 adds the multiplier columns.  0, or -1 on a write
 * error. */
int usm_sweep_csv(const usm_sweep *s, const char *over, int floquet, FILE *out);

/* The `usm sweep --json` object and a newline to out; p: the parameters apart
 * from the swept one.  0, or -1 on a write error or when out of memory. */
int usm_sweep_write_json(const usm_sweep *s, const usm_model *m, const usm_params *p,
                         const char *over, FILE *out);

/* ---- sensitivities -------------------------------------------------------------- */

/* The `usm sensitivity --json` object and a newline to out: for each output k
 * with want[k], its value, the derivatives "d" and the elasticities in every
 * parameter.  0, or -1 on a write error or when out of memory. */
int usm_sensitivity_write_json(const usm_model *m, const usm_params *p,
                               const usm_sensitivity_result *r, const int want[USM_SENS_COUNT],
                               FILE *out);

/* The table of `usm sensitivity`: per output the parameters by decreasing
 * |elasticity|. */
void usm_sensitivity_write_table(const usm_model *m, const usm_params *p,
                                 const usm_sensitivity_result *r, const int want[USM_SENS_COUNT],
                                 FILE *out);

/* ---- tables for people of one result ----------------------------------------- */

struct usm_periodic_result;
struct usm_hybrid_result;
struct usm_opt_problem;
struct usm_opt_result;
struct usm_robust_problem;
struct usm_robust_result;

/* The table of `usm periodic` for a periodic orbit of model m (usm_periodic.h):
 * the rotor speed, tilt, normal force, validity, Floquet multipliers and the
 * squeal frequency, speeds and angles in the display units d (--units; NULL:
 * SI).  An orbit the model does not describe says so before its values. */
void usm_periodic_write_table(const usm_model *m, const struct usm_periodic_result *r,
                              const usm_display *d, FILE *out);

/* The table of `usm periodic` for an orbit with separation (usm_periodic.h):
 * period, mode sequence, separations and impacts, validity and the
 * multipliers with saltation matrices; speeds in the display units d (NULL:
 * SI). */
void usm_hybrid_write_table(const usm_model *m, const struct usm_hybrid_result *r,
                            const usm_display *d, FILE *out);

/* The table of `usm optimize` (usm_optimize.h): the optimum of problem pb,
 * the varied parameters with their near-optimal intervals, the active
 * constraints' multipliers and the stationary solution there (SI: the
 * command takes no --units). */
void usm_optimize_write_table(const usm_model *m, const struct usm_opt_problem *pb,
                              const struct usm_opt_result *res, FILE *out);

/* The table of `usm optimize` for robust design (usm_robust.h): the robust
 * optimum with its yields, the active constraints, and the nominal optimum
 * when it is feasible (SI). */
void usm_robust_write_table(const usm_model *m, const struct usm_robust_problem *rp,
                            const struct usm_robust_result *res, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* USM_IO_H */
