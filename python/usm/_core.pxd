# _usm.pxd: the parts of libusm's public API (runtime/include/usm/, the
# generated headers) that the extension calls.  The structs
# are declared with the fields the extension uses; Cython takes their
# layout from the headers.

cdef extern from "usm.h" nogil:
    enum:
        USM_OK
        USM_EFAILED
        USM_EINPUT
        USM_ENOSOLUTION
        USM_MSG_LEN
        USM_FLOQUET_MAX_STEPS
        USM_NPARAMS
        USM_NMODELS
        USM_NVARIANTS
        USM_MAX_NX
        USM_MAX_NU

    ctypedef struct usm_params:
        double f

    ctypedef struct usm_param_info:
        const char *name
        const char *unit
        const char *description
        const char *constraint
        size_t offset

    const usm_param_info usm_param_table[]

    ctypedef struct usm_model:
        const char *name
        const char *base
        const char *variant
        const char *description
        const char *assumptions
        int nx
        int nu
        int t0_independent
        const char *const *state_names
        const char *const *unknown_names
        int slip
        int imperfect
        int coordinates
        int x_a
        int x_b
        void (*mass)(const double *x, const usm_params *p, double *out) nogil
        void (*rhs)(const double *x, double t, const usm_params *p, double *out) nogil
        void (*jac_rhs)(const double *x, double t, const usm_params *p, double *out) nogil
        void (*steady_residual)(const double *u, const usm_params *p, double *out) nogil
        void (*steady_jacobian)(const double *u, const usm_params *p, double *out) nogil

    const usm_model *const usm_models[]

    ctypedef struct usm_variant_info:
        const char *name
        const char *description

    const usm_variant_info usm_variants[]

    const char *usm_version()
    const char *usm_generator_version()
    const usm_model *usm_model_find(const char *name)
    const usm_model *usm_model_variant(const char *base, const char *variant)
    const usm_variant_info *usm_variant_find(const char *name)
    void usm_params_default(usm_params *p)
    const usm_param_info *usm_params_find(const char *name)
    int usm_param_index(const usm_param_info *info)
    double usm_params_get(const usm_params *p, const usm_param_info *info)
    int usm_params_set(usm_params *p, const char *name, double value, char *msg)
    int usm_params_check(const usm_params *p, const usm_model *m, char *msg)

    ctypedef enum usm_floquet_method:
        pass
    ctypedef struct usm_floquet_options:
        usm_floquet_method method
        double rtol
        double atol
        int steps
    void usm_floquet_options_default(usm_floquet_options *opt)
    int usm_floquet_method_from_name(const char *name, usm_floquet_method *method, char *msg)

    ctypedef struct usm_steady_solution:
        pass

cdef extern from "gsl/gsl_errno.h" nogil:
    ctypedef void gsl_error_handler_t(const char *, const char *, int, int)
    gsl_error_handler_t *gsl_set_error_handler_off()

cdef extern from "usm_io.h" nogil:
    enum:
        USM_IO_MSG_LEN
    int usm_parse_quantity(const char *field, const char *unit, const char *text, size_t len,
                           double *out, char *msg)

cdef extern from "usm_simulate.h" nogil:
    ctypedef enum usm_sim_start:
        USM_SIM_FROM_REST
        USM_SIM_FROM_STATIONARY
        USM_SIM_FROM_STATE
    ctypedef struct usm_sim_options:
        usm_sim_start start
        double t0
        double duration
        double tilt0
        double x0[9]
        double rotor_angle0
        double rate
        double rtol
        double settle_tol
        int settle_periods
        double theta_limit
        double speed_limit
        long max_steps
        double max_step
        double max_twist_growth
        double rest_fraction
    void usm_sim_options_default(usm_sim_options *opt)
    double usm_sim_default_rate(const usm_params *p)

cdef extern from "usm_operating_point.h" nogil:
    ctypedef struct usm_op_options:
        int from_rest
        double periods
        usm_sim_options sim
    void usm_op_options_default(usm_op_options *opt)

cdef extern from "usm_design.h" nogil:
    enum:
        USM_SENS_COUNT
    const char *usm_sensitivity_output_name(int k)
    int usm_sensitivity_output_find(const char *name)
    void usm_sensitivity_outputs_default(int *want)

cdef extern from "usm_sweep.h" nogil:
    ctypedef struct usm_steady_options:
        double theta_min
        double theta_max
        int grid
        double xtol
    ctypedef double (*usm_monitor_fn)(const usm_steady_solution *sol, const usm_params *p,
                                      void *ctx) nogil
    enum:
        USM_SWEEP_MAX_LEVELS
        USM_SWEEP_MAX_MONITORS
    ctypedef struct usm_sweep_monitor:
        const char *name
        usm_monitor_fn fn
        void *ctx
        int extrema
        int nlevels
        double levels[4]
    const char *USM_SWEEP_QUANTITIES
    const char *usm_sweep_quantity(const char *name, size_t len, usm_monitor_fn *fn)
    ctypedef struct usm_sweep_options:
        const char *over
        double from_ "from"
        double to
        int points
        int floquet
        double t0
        usm_floquet_options floquet_options
        int threads
        usm_steady_options steady
        const usm_sweep_monitor *monitors
        int nmonitors
        int operating_point
        usm_op_options op
    void usm_sweep_options_default(usm_sweep_options *opt)

cdef extern from "usm_periodic.h" nogil:
    ctypedef struct usm_periodic_options:
        double rtol
        double tol
        int max_iter
        double t0

cdef extern from "usm_periodic_sweep.h" nogil:
    ctypedef struct usm_periodic_sweep_options:
        const char *over
        double from_ "from"
        double to
        int points
        double event_tol
        usm_periodic_options periodic
    void usm_periodic_sweep_options_default(usm_periodic_sweep_options *opt)

cdef extern from "usm_squeal_study.h" nogil:
    ctypedef struct usm_squeal_options:
        const char *over
        double from_ "from"
        double to
        int points
        long settle
        long window
        int samples_per_period
        long lyapunov_skip
        long lyapunov_periods
        double rtol
        double lyapunov_rtol
        double period_tol
        double exponent_tol
        int check_rest
        int lines
        long power_periods
        int sensitivities
    void usm_squeal_options_default(usm_squeal_options *opt)

cdef extern from "usm_progress.h" nogil:
    ctypedef void (*usm_progress_fn)(void *ctx, long done, long total, const char *what)
    ctypedef struct usm_progress:
        usm_progress_fn fn
        void *ctx

cdef extern from "usm_map.h" nogil:
    ctypedef struct usm_map_axis:
        const char *name
        double from_ "from"
        double to
        int points
    ctypedef struct usm_map_options:
        usm_map_axis x
        usm_map_axis y
        double t0
        usm_floquet_options floquet
        int threads
        usm_op_options op
        usm_progress progress
    void usm_map_options_default(usm_map_options *opt)

cdef extern from "usm_envelope.h" nogil:
    ctypedef struct usm_envelope_axis:
        const char *name
        double lo
        double hi
    ctypedef struct usm_envelope_options:
        usm_envelope_axis x
        usm_envelope_axis y
        int lines
        int nodes
        double h_max
        int max_points
        int stability
        int raster
        double t0
        usm_floquet_options floquet
        usm_op_options op
    void usm_envelope_options_default(usm_envelope_options *opt)

cdef extern from "usm_optimize.h" nogil:
    ctypedef struct usm_opt_problem:
        int objective
        int minimize
        double margin
        int allow_slip
        int allow_driven
        int starts
        double t0
        int no_flat
        int from_rest
        double from_rest_periods
    void usm_opt_problem_init(usm_opt_problem *pb)
    int usm_opt_problem_add_vary(usm_opt_problem *pb, const char *name, double lo, double hi,
                                 char *msg)
    int usm_opt_problem_add_constraint(usm_opt_problem *pb, const char *output, int upper,
                                       double value, char *msg)
    int usm_opt_problem_check(const usm_opt_problem *pb, const usm_model *m, const usm_params *p,
                              char *msg)
    int usm_opt_output_find(const char *name)
    int usm_opt_output_analytic(int k)
    void usm_opt_output_list(char *buf, size_t len)

cdef extern from "usm.h" nogil:
    int usm_params_check_ideal(const usm_params *p, char *msg)

cdef extern from "usm_tolerance.h" nogil:
    enum:
        USM_TOL_NOUTPUTS
    ctypedef unsigned long long uint64_t
    const uint64_t USM_SEED_MAX
    const uint64_t USM_TOLERANCE_MAX_SAMPLES
    ctypedef struct usm_tolerance_vary:
        pass
    ctypedef struct usm_tolerance_spec:
        pass
    ctypedef struct usm_tolerance_options:
        uint64_t samples
        uint64_t seed
        int threads
        double t0
        usm_floquet_options floquet
        usm_op_options op
        int allow_driven
        usm_progress progress
    void usm_tolerance_options_default(usm_tolerance_options *opt)
    int usm_tolerance_vary_parse(const char *text, usm_tolerance_vary *v, char *msg)
    int usm_tolerance_vary_parse_units(const char *field, const char *text,
                                       usm_tolerance_vary *v, char *msg)
    int usm_tolerance_spec_parse(const char *text, usm_tolerance_spec *s, char *msg)
    const char *usm_tolerance_output_name(int k)

cdef extern from "usm_robust.h" nogil:
    const uint64_t USM_ROBUST_MIN_SAMPLES
    const uint64_t USM_ROBUST_MAX_SAMPLES
    enum:
        USM_ROBUST_MAX_SCATTER
        USM_PARETO_MAX_POINTS
    ctypedef struct usm_robust_range:
        int param
        double lo
        double hi
        int points
        int stat
    ctypedef struct usm_quantity_options:
        usm_robust_range range
        double band_threshold
    ctypedef struct usm_robust_problem:
        usm_opt_problem nominal
        int objective
        int nscatter
        usm_tolerance_vary scatter[16]
        uint64_t samples
        uint64_t seed
        uint64_t verify_samples
        int threads
        int max_evals
        usm_quantity_options qopt
    void usm_robust_problem_init(usm_robust_problem *rp)
    int usm_robust_problem_is_robust(const usm_robust_problem *rp)
    int usm_robust_problem_check(const usm_robust_problem *rp, const usm_model *m,
                                 const usm_params *p, char *msg)
    int usm_robust_objective_parse(usm_robust_problem *rp, const char *text, char *msg)
    int usm_pareto_objectives_parse(const char *text, int *output, int *minimize, char *msg)
    int usm_robust_constraint_parse(usm_robust_problem *rp, const char *text, char *msg)
    int usm_range_stat_find(const char *name)

cdef extern from "usm_spectrum.h" nogil:
    enum:
        USM_SPECTRUM_NCHANNELS
    ctypedef struct usm_sim_spectrum_result:
        double f
        double df
        size_t bins
    const char *usm_spectrum_channel_name(int channel)

cdef extern from "usm_fit.h" nogil:
    ctypedef struct usm_fit_options:
        int starts
    void usm_fit_options_default(usm_fit_options *o)

cdef extern from "usm_run.h" nogil:
    enum:
        USM_RUN_SIM_COLUMNS
    ctypedef struct usm_run:
        pass
    int usm_run_status(const usm_run *r)
    const char *usm_run_message(const usm_run *r)
    int usm_run_has_json(const usm_run *r)
    char *usm_run_json(const usm_run *r, size_t *len)
    const double *usm_run_rows(usm_run *r, size_t *nrows, size_t *ncols)
    void usm_run_free(usm_run *r)
    usm_run *usm_run_steady(const usm_model *m, const usm_params *p, double t0,
                            const usm_floquet_options *fo, const usm_op_options *op)
    usm_run *usm_run_sensitivity(const usm_model *m, const usm_params *p, const int *want)
    usm_run *usm_run_fit(const usm_model *m, const usm_params *p, const char *path,
                         const char *text, size_t len, const char *names,
                         const usm_fit_options *opt)
    usm_run *usm_run_periodic(const usm_model *m, const usm_params *p)
    usm_run *usm_run_simulate(const usm_model *m, const usm_params *p, const usm_sim_options *opt,
                              const void *cb, long spectrum_periods)
    const usm_sim_spectrum_result *usm_run_spectrum(const usm_run *r)
    const double *usm_run_spectrum_amplitudes(const usm_run *r, int channel)
    usm_run *usm_run_sweep(const usm_model *m, const usm_params *p, const usm_sweep_options *opt)
    usm_run *usm_run_periodic_sweep(const usm_model *m, const usm_params *p,
                                    const usm_periodic_sweep_options *opt)
    usm_run *usm_run_squeal(const usm_model *m, const usm_params *p, const usm_squeal_options *opt)
    usm_run *usm_run_map(const usm_model *m, const usm_params *p, const usm_map_options *opt)
    usm_run *usm_run_envelope(const usm_model *m, const usm_params *p,
                              const usm_envelope_options *opt)
    usm_run *usm_run_optimize(const usm_model *m, const usm_params *p, const usm_opt_problem *pb)
    usm_run *usm_run_robust(const usm_model *m, const usm_params *p, const usm_robust_problem *rp)
    usm_run *usm_run_pareto(const usm_model *m, const usm_params *p, const usm_opt_problem *pb,
                            const int *obj, const int *minimize, int points)
    usm_run *usm_run_tolerance(const usm_model *m, const usm_params *p,
                               const usm_tolerance_vary *vary, int nvary,
                               const usm_tolerance_spec *spec, int nspec,
                               const usm_tolerance_options *opt, void *runner)
