/* envelope_internal.h: the envelope's state, shared by envelope.c (curves)
 * and envelope_regions.c (regions).  Not installed; not part of the API. */
#ifndef USM_ENVELOPE_INTERNAL_H
#define USM_ENVELOPE_INTERNAL_H

#include "usm_cont.h"
#include "usm_envelope.h"
#include "usm_periodic.h"

#define ENV_MAX_TESTS 16

typedef struct env_seed {
    int kind;
    double u[USM_MAX_NU];
    double x, y;
} env_seed;

typedef struct env_curve {
    usm_envelope_curve pub;
    double *xy, *u;
    double *freq;               /* the imperfect models' stability curves (else NULL) */
} env_curve;

struct usm_envelope {
    const usm_model *m;
    int nu;
    usm_params p;
    usm_envelope_options opt;
    const usm_param_info *ax[2];
    int col[2];                 /* the axes' columns of steady_jacobian_params */
    double lo[2], hi[2];
    usm_steady *steady;
    usm_floquet *fl;
    env_seed *seeds;
    size_t nseeds, seedcap, seeds_dropped;
    env_curve *curves;
    size_t ncurves, curvecap;
    usm_envelope_codim2 *codim2;
    size_t ncodim2, codim2cap;
    usm_envelope_region *regions;
    size_t nregions, regioncap;
    int *label;                 /* raster x raster: region index, -1 on a curve */
    struct env_hseeds *hseeds;  /* the edge sweeps' folds of orbits with separation
                                   (envelope_hybrid.c) */
    struct env_gseeds *gseeds;  /* their branch ends where the closed phases vanish
                                   (envelope_hybrid_grazing.c) */
    char msg[USM_MSG_LEN];
};

struct env_problem;
typedef struct env_test {
    struct env_problem *pb;
    int what;                   /* envelope.c's TEST_* */
    int kind;                   /* TEST_KIND: the defining function */
    int side;                   /* TEST_BOX: 0 x low, 1 x high, 2 y low, 3 y high */
    int index;                  /* the engine's */
} env_test;

/* A zero problem posed to the engine: a seed line (kind < 0: u and the
 * line's parameter free) or a curve of `kind` (u and both parameters). */
typedef struct env_problem {
    usm_envelope *e;
    usm_params p;               /* working copy */
    int kind;
    int line_axis;              /* a line: its free parameter (0 x, 1 y) */
    double fixed;               /* and the other's value */
    int swap;                   /* a curve: 0 x = (u, px, py), 1 x = (u, py, px) */
    int n;                      /* equations */
    double scale[USM_MAX_NU + 2];
    double uscale[USM_MAX_NU];  /* the fold's scaled unknowns (fixed per curve) */
    double border_b[USM_MAX_NU], border_c[USM_MAX_NU];
    double sat_w;               /* friction_saturation: the rotor speed W held */
    usm_cont *cont;
    /* a fold curve's multipliers at fl_x (its two Floquet tests share them) */
    double fl_x[USM_MAX_NU + 2];
    usm_floquet_result fl_res;
    int fl_valid;
    env_test tests[ENV_MAX_TESTS];
    int ntests;
} env_problem;

/* The two parameters of x in the problem's layout. */
void env_xy(const env_problem *pb, const double *x, double *px, double *py);
/* Defining function `kind` at x (the problem's parameters set from x). */
double env_defining(env_problem *pb, int kind, const double *x);
const env_test *env_test_of(const env_problem *pb, int index);
int env_kind_applies(const usm_envelope *e, int kind);
/* A codimension-two point (once: one within 1e-6 of the box of a kept one
 * is that one); u: nu values.  0, or -1 when out of memory. */
int env_add_codim2(usm_envelope *e, const char *type, const double *u, double px, double py,
                   size_t curve);

/* The results of the last run freed and counted 0 (envelope_result.c). */
void env_clear_result(usm_envelope *e);

/* A curve's points (x, y) as they are traced, for the curves that keep no
 * state a point (the orbits with separation's). */
typedef struct env_xy_buf {
    double *xy;
    size_t n, cap;
} env_xy_buf;
/* (px, py) appended: 0, or -1 when out of memory. */
int env_xy_push(env_xy_buf *b, double px, double py);
/* b's points kept as a curve of `kind` with ends e0, e1 (b emptied; fewer
 * than two points are dropped, no curve): 0, or -1 when out of memory. */
int env_keep_xy_curve(usm_envelope *e, int kind, env_xy_buf *b, usm_envelope_end e0,
                      usm_envelope_end e1);

/* envelope_regions.c: the raster, its regions and their classes.  USM_OK,
 * USM_EINPUT or USM_EFAILED with e->msg. */
int env_regions(usm_envelope *e);

/* envelope_periodic.c: the imperfect models' contact_loss and stick_loss
 * curves (usm_envelope.h), and a region's class by its periodic orbit.
 * USM_OK or USM_EFAILED with e->msg. */
int env_periodic_curves(usm_envelope *e);
int env_periodic_classify(usm_envelope *e, usm_envelope_region *r);

/* envelope_periodic_stability.c: the imperfect models' curve of the
 * critical multiplier through the sweep's event along edge `edge` (0 x =
 * lo, 1 x = hi, 2 y = lo, 3 y = hi) at (x, y): crossing
 * USM_CROSSING_NEIMARK_SACKER or PERIOD_DOUBLING (kind stability) or FOLD
 * (kind fold; x0 then an orbit of the branch near the fold, (x, y) its
 * parameters, the fold found from it with the edge's parameter held),
 * continued into the box on w (usm_periodic_alloc of e->m) and kept as a
 * curve of e.  0 (also when it is lost at its start), or -1 when out of
 * memory. */
int env_periodic_stability_trace(usm_envelope *e, usm_periodic *w, int edge, int crossing,
                                 double x, double y, const double *x0);

/* envelope_hybrid.c: the folds of the orbits with separation (unilateral
 * models), curve kind separation_fold.  env_hybrid_seed keeps the event ev
 * of the sweep along edge `edge` (0 x = lo, 1 x = hi, 2 y = lo, 3 y = hi)
 * when it is such a fold (0, or -1 when out of memory); env_hybrid_curves
 * traces the kept seeds' curves when run is 1, and frees them (USM_OK, or
 * USM_EFAILED with e->msg when out of memory). */
struct usm_periodic_event;
int env_hybrid_seed(usm_envelope *e, int edge, const struct usm_periodic_event *ev);
int env_hybrid_curves(usm_envelope *e, int run);

/* envelope_hybrid_grazing.c: where the orbit with separation's closed
 * phases vanish, curve kind separation_grazing; called from the two above
 * alike (env_hybrid_seed passes every event, env_hybrid_curves runs and
 * frees the kept seeds). */
int env_grazing_seed(usm_envelope *e, int edge, const struct usm_periodic_event *ev);
int env_grazing_curves(usm_envelope *e, int run);

/* envelope_hybrid_regions.c: a unilateral model's region whose bilateral
 * orbit's contact opens (or that has none) classed by the orbit with
 * separation from rest at its sample (`separating`, `separating_unstable`);
 * r unchanged but for the message where there is none. */
void env_hybrid_classify(usm_envelope *e, usm_envelope_region *r);

#endif /* USM_ENVELOPE_INTERNAL_H */
