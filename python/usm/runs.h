/* runs.h: the analyses of the Python module as the usm command runs them
 * (runtime/cli/NAME_cmd.c: the same library calls in the same order, with the
 * same options), each written by the library's own JSON writer into memory.
 * The Python side parses that text: a result's .to_dict() is the command's
 * --json object, key for key and bit for bit, whatever keys the writers gain.
 *
 * Pure C, no Python: called by _core.pyx with the GIL released.  Every
 * function fills a usmpy_out: status (USM_OK, USM_EINPUT, USM_ENOSOLUTION,
 * USM_EFAILED), the message the command would print (without "usm: "), and
 * the JSON text (malloc'd, NUL-terminated; NULL where the command prints
 * none).  usmpy_out_free releases it.
 */
#ifndef USMPY_RUNS_H
#define USMPY_RUNS_H

#include <stddef.h>

#include "usm.h"
#include "usm_design.h"
#include "usm_io.h"
#include "usm_map.h"
#include "usm_operating_point.h"
#include "usm_optimize.h"
#include "usm_periodic.h"
#include "usm_periodic_sweep.h"
#include "usm_report_map.h"
#include "usm_simulate.h"
#include "usm_sweep.h"
#include "usm_tolerance.h"

typedef struct usmpy_out {
    int status;
    char msg[USM_IO_MSG_LEN];
    char *json;
    size_t len;
    /* simulate: the time history, rows x cols row-major (malloc'd), or NULL */
    double *rows;
    size_t nrows, ncols;
} usmpy_out;

void usmpy_out_init(usmpy_out *o);
void usmpy_out_free(usmpy_out *o);

/* usm steady --json [--t0 S] [--floquet-method M --rtol R] [--from-rest ...]
 * in two steps, so that a caller pays for the JSON only when it reads it:
 * usmpy_steady_run computes (status and message in o, no JSON) and returns
 * the state (NULL after USM_EINPUT, USM_EFAILED or out of memory; after
 * USM_ENOSOLUTION the state of the converged = false object);
 * usmpy_steady_json writes its JSON into o (status USM_OK, or USM_EFAILED
 * when out of memory); usmpy_steady_state_free frees it.  usmpy_steady does
 * all three. */
typedef struct usmpy_steady_state usmpy_steady_state;
usmpy_steady_state *usmpy_steady_run(const usm_model *m, const usm_params *p, double t0,
                                     const usm_floquet_options *fo, const usm_op_options *op,
                                     usmpy_out *o);
void usmpy_steady_json(const usmpy_steady_state *st, usmpy_out *o);
void usmpy_steady_state_free(usmpy_steady_state *st);
void usmpy_steady(const usm_model *m, const usm_params *p, double t0,
                  const usm_floquet_options *fo, const usm_op_options *op, usmpy_out *o);

/* usm sweep --json --over ... (sweep_cmd.c run); periodic: usm sweep --periodic */
void usmpy_sweep(const usm_model *m, const usm_params *p, const usm_sweep_options *opt,
                 usmpy_out *o);
void usmpy_periodic_sweep(const usm_model *m, const usm_params *p,
                          const usm_periodic_sweep_options *opt, usmpy_out *o);

/* usm simulate --json (the summary; its wall_time measured here as the
 * command measures it) and its time history: the CSV's numeric columns
 * (usm_sim_csv_header), a non-existing value NaN, then the validity
 * (usm_validity: 0 valid, 1 contact open, 2 stick not admissible) */
#define USMPY_SIM_COLUMNS 15
void usmpy_simulate(const usm_model *m, const usm_params *p, const usm_sim_options *opt,
                    usmpy_out *o);

/* usm periodic --json */
void usmpy_periodic(const usm_model *m, const usm_params *p, usmpy_out *o);

/* usm sensitivity --json [--of ...] */
void usmpy_sensitivity(const usm_model *m, const usm_params *p, const int want[USM_SENS_COUNT],
                       usmpy_out *o);

/* usm map --json */
void usmpy_map(const usm_model *m, const usm_params *p, const usm_map_options *opt,
               usmpy_out *o);

/* usm optimize --json (optimize_cmd.c): pb built and checked by the caller
 * (usm_opt_problem_check); the JSON also after USM_ENOSOLUTION ({"feasible":
 * false, ...}) */
void usmpy_optimize(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                    usmpy_out *o);

/* usm tolerance --json (tolerance_cmd.c, one process): the varied
 * parameters and specs as the library parsed them; o->rows: one row per
 * sample, the varied parameters' values, the USM_TOL_NOUTPUTS outputs, good
 * and redraws (usm_tolerance_sample). */
void usmpy_tolerance(const usm_model *m, const usm_params *p, const usm_tolerance_vary *vary,
                     int nvary, const usm_tolerance_spec *spec, int nspec,
                     const usm_tolerance_options *opt, usmpy_out *o);

#endif /* USMPY_RUNS_H */
