/* usm_run.h: each analysis of the usm command as one library call.
 *
 * A command of runtime/cli/ and the Python package (python/) run an analysis
 * the same way: usm_run_NAME does the library calls of `usm NAME` in the
 * command's order with the command's options, and keeps what the command
 * prints: the outcome (usm_run_status), the message it prints on a failure
 * (usm_run_message, without "usm: "), and the `usm NAME --json` object
 * (usm_run_write_json, usm_run_json) where the command prints one for that
 * outcome (usm_run_has_json).  What only the command does (options, files,
 * figures, progress bars, tables for people) stays in the command; the
 * typed accessors below give it the results.
 *
 * Every usm_run_NAME returns a run, or NULL when out of memory; a run is
 * freed by usm_run_free.  Inputs are copied or must outlive the run where
 * said.  Thread safety: no global state; distinct runs may be made and read
 * from distinct threads at the same time.
 */
#ifndef USM_RUN_H
#define USM_RUN_H

#include <stddef.h>
#include <stdio.h>

#include "usm.h"
#include "usm_design.h"
#include "usm_envelope.h"
#include "usm_fit.h"
#include "usm_io.h"
#include "usm_map.h"
#include "usm_operating_point.h"
#include "usm_optimize.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"
#include "usm_robust.h"
#include "usm_simulate.h"
#include "usm_spectrum.h"
#include "usm_squeal_study.h"
#include "usm_sweep.h"
#include "usm_tolerance.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One analysis' outcome (opaque). */
typedef struct usm_run usm_run;

/* USM_OK, USM_EINPUT (bad input), USM_ENOSOLUTION (no solution: usm steady's
 * exit 3), USM_EFAILED (numerical failure, out of memory): the command's exit
 * status. */
int usm_run_status(const usm_run *r);
/* The one-line message the command prints for a status other than USM_OK
 * ("" for USM_OK; a run that stopped early: why), without "usm: ". */
const char *usm_run_message(const usm_run *r);
/* Whether `usm NAME --json` prints an object for this outcome (also for
 * some failures: steady's converged = false, periodic's "error",
 * optimize's "feasible": false, a simulation that stopped early). */
int usm_run_has_json(const usm_run *r);
/* That object and a newline to out: 0, or -1 on a write error, when out of
 * memory, or when usm_run_has_json is 0. */
int usm_run_write_json(const usm_run *r, FILE *out);
/* The same text in a malloc'd NUL-terminated buffer (*len: its length
 * without the NUL; len may be NULL), or NULL (out of memory, or no JSON). */
char *usm_run_json(const usm_run *r, size_t *len);
/* Numbers of a run as rows: simulate's time history (usm_run_simulate with
 * no sample callback: USM_RUN_SIM_COLUMNS), tolerance's samples (the varied
 * parameters, the USM_TOL_NOUTPUTS outputs, good, redraws; made at the
 * first call).  Row-major, owned by r; NULL with *nrows = 0 where there are
 * none (or out of memory). */
const double *usm_run_rows(usm_run *r, size_t *nrows, size_t *ncols);
/* Free r; NULL is allowed. */
void usm_run_free(usm_run *r);

/* ---- the analyses ---------------------------------------------------------------- */

/* usm steady [--t0 S] [--floquet-method ... --rtol ...] [--from-rest ...]:
 * every root, the multipliers of each, the operating point.  Status
 * USM_ENOSOLUTION: JSON converged = false. */
usm_run *usm_run_steady(const usm_model *m, const usm_params *p, double t0,
                        const usm_floquet_options *fo, const usm_op_options *op);
/* The report of a steady run for usm_steady_table (NULL unless USM_OK). */
const usm_steady_report *usm_run_steady_report(const usm_run *r);

/* usm sensitivity [--of ...]: want[k] != 0 for the outputs asked for
 * (copied). */
usm_run *usm_run_sensitivity(const usm_model *m, const usm_params *p,
                             const int want[USM_SENS_COUNT]);
/* The derivatives of a sensitivity run (NULL unless USM_OK). */
const usm_sensitivity_result *usm_run_sensitivity_result(const usm_run *r);

/* usm periodic: the shooting; for a unilateral model whose orbit opens the
 * contact (or has none), the orbit with separation (usm_hybrid_solve). */
usm_run *usm_run_periodic(const usm_model *m, const usm_params *p);
/* The bilateral orbit, or NULL (failed, or the orbit with separation). */
const usm_periodic_result *usm_run_periodic_result(const usm_run *r);
/* The bilateral orbit's solver (for usm_periodic_write_orbit_csv), or NULL. */
const usm_periodic *usm_run_periodic_solver(const usm_run *r);
/* The orbit with separation, or NULL (failed, or bilateral). */
const usm_hybrid_result *usm_run_hybrid_result(const usm_run *r);

/* The columns of a simulation's kept history (usm_run_simulate). */
#define USM_RUN_SIM_COLUMNS 15

/* usm simulate (--json's summary, its wall time measured around
 * usm_sim_run).  cb: the caller's callbacks (the command's CSV rows and
 * progress bar), or NULL: then with opt->rate > 0 the time history is kept
 * (usm_run_rows, USM_RUN_SIM_COLUMNS: t, phi, theta, psi, phidot,
 * thetadot, psidot, phi_R, phi_Rdot, F_n, F_t, v_rel, theta_avg,
 * phi_Rdot_avg (NaN before the first period), validity (usm_validity)).
 * spectrum_periods >= 0: the spectrum of the samples (--spectrum:
 * usm_sim_spectrum_compute with periods = spectrum_periods, 0: the default
 * window), in the summary without its CSV file.  Status: USM_OK;
 * USM_EINPUT, USM_ENOSOLUTION (no JSON); USM_EFAILED with JSON: the run
 * stopped early, or the spectrum could not be computed ("spectrum_...";
 * usm_run_spectrum_error says why).  Options that the library names
 * ("duration: ...") are named so in the messages; the spectrum's options
 * "spectrum_periods", "spectrum_rate" ... */
usm_run *usm_run_simulate(const usm_model *m, const usm_params *p, const usm_sim_options *opt,
                          const usm_sim_callbacks *cb, long spectrum_periods);
/* The summary of a simulate run that ran (USM_OK or USM_EFAILED), or NULL. */
const usm_sim_summary *usm_run_sim_summary(const usm_run *r);
/* The summary's report for usm_sim_write_json / usm_sim_write_table: model,
 * parameters, options, summary, wall time, spectrum (or its error); the
 * caller adds what only it knows (from_file, out, spectrum_csv).  All zero
 * for a run without summary. */
void usm_run_sim_report(const usm_run *r, usm_sim_report *rep);
/* The spectrum of a simulate run (NULL: none). */
const usm_sim_spectrum_result *usm_run_spectrum(const usm_run *r);
/* Why a simulate run asked for a spectrum has none (the library's reason,
 * "periods: ..."; "out of memory recording the samples"), or NULL. */
const char *usm_run_spectrum_error(const usm_run *r);
/* The amplitudes of channel c (USM_SPECTRUM_*) of a simulate run's
 * spectrum: spectrum->bins values, bin k at k df; NULL without one. */
const double *usm_run_spectrum_amplitudes(const usm_run *r, int channel);
/* The spectrum as usm_sim_spectrum_write_csv writes it: 0, or -1 (a write
 * error, or no spectrum). */
int usm_run_spectrum_write_csv(const usm_run *r, FILE *out);

/* usm squeal: the motion over one parameter beyond the last periodic orbit
 * (usm_squeal_study.h); opt's pointers must outlive the call only.  JSON:
 * usm_squeal_write_json's object. */
usm_run *usm_run_squeal(const usm_model *m, const usm_params *p, const usm_squeal_options *opt);
/* The study of a squeal run for its CSV and plot writers (NULL unless USM_OK). */
const usm_squeal_study *usm_run_squeal_result(const usm_run *r);

/* usm sweep: opt's pointers (monitors) must outlive the call only. */
usm_run *usm_run_sweep(const usm_model *m, const usm_params *p, const usm_sweep_options *opt);
/* The sweep of a sweep run for its CSV and plot writers (NULL unless USM_OK). */
const usm_sweep *usm_run_sweep_result(const usm_run *r);
/* usm sweep --periodic */
usm_run *usm_run_periodic_sweep(const usm_model *m, const usm_params *p,
                                const usm_periodic_sweep_options *opt);
/* The periodic sweep of such a run (NULL unless USM_OK). */
const usm_periodic_sweep *usm_run_periodic_sweep_result(const usm_run *r);

/* usm map: opt as usm_report_map_options makes it (opt->boundaries: 1 for
 * --json); its strings are copied. */
usm_run *usm_run_map(const usm_model *m, const usm_params *p, const usm_map_options *opt);
/* The map for the writers of usm_report_map.h (NULL unless USM_OK). */
const struct usm_report_map *usm_run_map_result(const usm_run *r);

/* usm envelope: the curves, codimension-two points and regions of the box
 * (usm_envelope_run); opt's strings must outlive the run.  The JSON is
 * usm_envelope_write_json's. */
usm_run *usm_run_envelope(const usm_model *m, const usm_params *p,
                          const usm_envelope_options *opt);
/* The envelope of such a run for its CSV writer (NULL unless USM_OK). */
const usm_envelope *usm_run_envelope_result(const usm_run *r);

/* usm optimize: pb checked by the caller (usm_opt_problem_check); copied.
 * USM_ENOSOLUTION: JSON {"feasible": false, ...} and the message. */
usm_run *usm_run_optimize(const usm_model *m, const usm_params *p, const usm_opt_problem *pb);
/* The optimum of an optimize run (NULL unless USM_OK). */
const usm_opt_result *usm_run_optimize_result(const usm_run *r);
/* usm optimize with a robust problem (usm_robust_problem_is_robust; checked
 * by the caller); copied. */
usm_run *usm_run_robust(const usm_model *m, const usm_params *p, const usm_robust_problem *rp);
/* The robust optimum (NULL unless it has JSON: USM_OK or no feasible design). */
const usm_robust_result *usm_run_robust_result(const usm_run *r);

/* usm pareto: pb as usm_pareto_run's (copied). */
usm_run *usm_run_pareto(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                        const int obj[2], const int minimize[2], int points);
/* The front of a pareto run (NULL unless USM_OK). */
const usm_pareto_result *usm_run_pareto_result(const usm_run *r);

/* usm tolerance: the varied parameters and specs as usm_tolerance_vary_parse
 * / usm_tolerance_spec_parse made them (message "vary ..." or "spec ..."
 * when the study refuses one); runner: NULL for usm_tolerance_run, or a
 * function of its signature (the command's usm_tolerance_run_mpi).  Its rows
 * (usm_run_rows, made when first asked for): per sample the varied
 * parameters' values, the USM_TOL_NOUTPUTS outputs, good, redraws. */
typedef int (*usm_tolerance_runner)(usm_tolerance *t, const usm_params *p,
                                    const usm_tolerance_options *opt);
/* usm tolerance, as described above. */
usm_run *usm_run_tolerance(const usm_model *m, const usm_params *p,
                           const usm_tolerance_vary *vary, int nvary,
                           const usm_tolerance_spec *spec, int nspec,
                           const usm_tolerance_options *opt, usm_tolerance_runner runner);
/* The study (for its writers; usm_tolerance_output_seconds_add), or NULL
 * when it was not made. */
usm_tolerance *usm_run_tolerance_result(usm_run *r);

/* usm fit --data FILE.csv --fit NAME[,NAME...] (usm_fit.h): the measurements
 * read from the file at path (usm_fit_data_read), or, with text not NULL,
 * from its len bytes (path names them in messages); names: the fitted
 * parameters (usm_fit_parse_names, NULL: those of opt); opt: NULL for the
 * defaults (usm_fit_options_default); copied.  Status USM_EINPUT (bad data
 * or names: one line naming the column or field and the reason), or the
 * fit's (usm_fit_run). */
usm_run *usm_run_fit(const usm_model *m, const usm_params *p, const char *path, const char *text,
                     size_t len, const char *names, const usm_fit_options *opt);
/* The result of a fit run (NULL unless USM_OK). */
const usm_fit_result *usm_run_fit_result(const usm_run *r);
/* The measurements of a fit run (NULL when they could not be read). */
const usm_fit_data *usm_run_fit_data(const usm_run *r);

#ifdef __cplusplus
}
#endif

#endif /* USM_RUN_H */
