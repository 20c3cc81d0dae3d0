/* Where the stable orbit with separation ends, located, and how the design
 * parameters move it (usm_squeal_locate_onset, usm_squeal_onset_sensitivities;
 * usm_squeal_study.h, docs/squeal.md "The onset and its sensitivities").
 *
 * The orbit is continued in the parameter from a solved one by Newton
 * (usm_hybrid_solve_from), each new section in the middle of the last
 * orbit's longest closed phase (the closed phase shrinks and moves as the
 * end nears: a section kept where it was falls into the air), in steps of
 * an eighth of the range, halved where Newton fails, until the last orbit
 * and the first failure are within tol of each other: the end of the
 * branch (at the 3-DOF phase error's end its closed fraction stalls near
 * 0.5 % of the period while the steps shrink to 1e-9 rad: the branch turns
 * back there, a fold of the orbit with separation as far as is seen).
 * Where an orbit on the way is unstable (largest non-cyclic |lambda| >= 1)
 * the branch loses stability first: the onset is then the zero of
 * max |lambda| - 1 by the secant (regula falsi, Illinois) between the last
 * stable orbit and that one.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "usm_periodic.h"
#include "usm_squeal_study.h"

#define SAMPLES 400   /* a period's samples for the next section */
#define MAX_SOLVES 120

typedef struct walker {
    usm_hybrid *h;
    usm_params p;
    const usm_param_info *info;
    usm_hybrid_options ho;
    double *rows;
    int solves;
    char msg[USM_MSG_LEN];
} walker;

/* The orbit at parameter value v from the section (ts, x0): 0, or -1. */
static int orbit_at(walker *w, double v, double ts, const double *x0, usm_hybrid_result *r)
{
    usm_params q = w->p;
    *usm_params_field(&q, w->info) = v;
    ++w->solves;
    return usm_hybrid_solve_from(w->h, &q, &w->ho, ts, x0, r) == USM_OK && r->converged ? 0 : -1;
}

/* The middle of the longest closed phase of orbit r at v as the next
 * section (*ts, x); 0, or -1. */
static int resection(walker *w, double v, const usm_hybrid_result *r, double *ts, double *x)
{
    usm_params q = w->p;
    *usm_params_field(&q, w->info) = v;
    const int nx = r->nx, C = USM_HYBRID_SAMPLE_COLS(nx);
    int nr = 0;
    if (usm_hybrid_orbit_samples(w->h, &q, r, w->ho.rtol, SAMPLES, w->rows, &nr) != USM_OK ||
        nr < 2)
        return -1;
    /* the closed stretches, the period wrapped (the section is in one) */
    int best_a = -1, best_len = 0;
    for (int a = 0; a < nr; ++a) {
        if (w->rows[(size_t)a * C + 1] != 0.0 || (a > 0 && w->rows[(size_t)(a - 1) * C + 1] == 0.0))
            continue;
        int b = a;
        while (b + 1 < nr && w->rows[(size_t)(b + 1) * C + 1] == 0.0)
            ++b;
        if (b - a + 1 > best_len) {
            best_len = b - a + 1;
            best_a = a;
        }
    }
    if (best_a < 0)
        return -1;
    const double *row = w->rows + (size_t)(best_a + best_len / 2) * C;
    *ts = row[0];
    memcpy(x, row + 2, sizeof(double) * (size_t)nx);
    return 0;
}

int usm_squeal_locate_onset(const usm_model *m, const usm_params *p, const char *over,
                            double value, double toward, double ts, const double *x0, double tol,
                            usm_squeal_onset *out)
{
    memset(out, 0, sizeof *out);
    out->value = NAN;
    const usm_param_info *info = usm_params_find(over ? over : "");
    if (!m->unilateral || !info || !(tol > 0) || !isfinite(value) || !isfinite(toward) ||
        value == toward) {
        snprintf(out->message, USM_MSG_LEN, "%s",
                 !m->unilateral ? "model: its contact never opens"
                 : !info        ? "over: unknown parameter"
                 : !(tol > 0)   ? "tol: must be positive"
                                : "value, toward: must be finite and different");
        return USM_EINPUT;
    }
    walker w;
    memset(&w, 0, sizeof w);
    w.p = *p;
    w.info = info;
    usm_hybrid_options_default(&w.ho);
    w.h = usm_hybrid_alloc(m);
    w.rows = malloc(sizeof(double) * (size_t)USM_HYBRID_SAMPLE_ROWS(SAMPLES) *
                    (size_t)USM_HYBRID_SAMPLE_COLS(USM_MAX_NX));
    int rc = USM_OK;
    if (!w.h || !w.rows) {
        snprintf(out->message, USM_MSG_LEN, "out of memory");
        rc = USM_EFAILED;
        goto done;
    }
    usm_hybrid_result a, b;
    double va = value, sa, xa[USM_MAX_NX];
    usm_params q = *p;
    *usm_params_field(&q, info) = value;
    ++w.solves;
    /* from the given section, or (none, or Newton fails from it: a changed
       frequency moves the phase of a distant section) from rest */
    int ok = x0 && usm_hybrid_solve_from(w.h, &q, &w.ho, ts, x0, &a) == USM_OK && a.converged;
    if (!ok) {
        ++w.solves;
        ok = usm_hybrid_solve(w.h, &q, &w.ho, &a) == USM_OK && a.converged;
    }
    if (!ok) {
        snprintf(out->message, USM_MSG_LEN, "no orbit with separation at %s = %g: %.150s", over,
                 value, usm_hybrid_message(w.h));
        goto done;
    }
    if (a.floquet.max_modulus >= 1.0) {
        snprintf(out->message, USM_MSG_LEN, "the orbit at %s = %g is unstable (max |lambda| %.6g)",
                 over, value, a.floquet.max_modulus);
        goto done;
    }
    if (resection(&w, va, &a, &sa, xa) != 0) {
        snprintf(out->message, USM_MSG_LEN, "the orbit at %g has no closed phase to section", va);
        goto done;
    }
    const double range = toward - value, dir = range > 0 ? 1.0 : -1.0;
    double step = range / 8.0;
    while (w.solves < MAX_SOLVES) {
        if (fabs(step) <= tol * fabs(range))
            break;
        const double vb = va + step;
        if ((vb - toward) * dir > 0) { /* the range holds no end */
            snprintf(out->message, USM_MSG_LEN, "the orbit continues to %s = %g", over, toward);
            goto done;
        }
        if (orbit_at(&w, vb, sa, xa, &b) != 0) {
            step *= 0.5;
            continue;
        }
        if (b.floquet.max_modulus >= 1.0) {
            /* stability lost first: regula falsi (Illinois) on max |lambda| - 1 */
            double lo = va, hi = vb, flo = a.floquet.max_modulus - 1.0,
                   fhi = b.floquet.max_modulus - 1.0, s_lo = sa;
            double x_lo[USM_MAX_NX];
            memcpy(x_lo, xa, sizeof x_lo);
            int side = 0;
            while (fabs(hi - lo) > tol * fabs(range) && w.solves < MAX_SOLVES) {
                const double vm = lo - flo * (hi - lo) / (fhi - flo);
                usm_hybrid_result c;
                if (orbit_at(&w, vm, s_lo, x_lo, &c) != 0)
                    break;
                const double fm = c.floquet.max_modulus - 1.0;
                if (fm < 0) {
                    lo = vm, flo = fm;
                    resection(&w, vm, &c, &s_lo, x_lo);
                    if (side == -1)
                        fhi *= 0.5;
                    side = -1;
                } else {
                    hi = vm, fhi = fm;
                    if (side == 1)
                        flo *= 0.5;
                    side = 1;
                }
            }
            out->value = lo - flo * (hi - lo) / (fhi - flo);
            snprintf(out->kind, sizeof out->kind, "stability_loss");
            out->closed_fraction = 1.0 - a.separation_fraction;
            out->found = 1;
            goto done;
        }
        va = vb, a = b;
        if (resection(&w, va, &a, &sa, xa) != 0) {
            snprintf(out->message, USM_MSG_LEN, "the orbit at %g has no closed phase to section",
                     va);
            goto done;
        }
    }
    if (w.solves >= MAX_SOLVES) {
        snprintf(out->message, USM_MSG_LEN, "no end located in %d orbit solves", MAX_SOLVES);
        goto done;
    }
    /* no orbit at va + 2 step (the last failure), one at va: the end between */
    out->value = va + step;
    out->closed_fraction = 1.0 - a.separation_fraction;
    out->last_orbit = va;
    snprintf(out->kind, sizeof out->kind, "branch_end");
    out->found = 1;
done:
    out->solves = w.solves;
    usm_hybrid_free(w.h);
    free(w.rows);
    return rc;
}

const char *const usm_squeal_design_parameters[USM_SQUEAL_DESIGN_PARAMETERS] = {
    "F0", "mu0", "f", "T", "m0"};

int usm_squeal_onset_sensitivities(const usm_model *m, const usm_params *p, const char *over,
                                   double value, double toward, double ts, const double *x0,
                                   const char *const *names, int nnames, double h, double tol,
                                   usm_squeal_onset *out)
{
    memset(out, 0, sizeof *out);
    out->value = NAN;
    if (!names) {
        names = usm_squeal_design_parameters;
        nnames = USM_SQUEAL_DESIGN_PARAMETERS;
    }
    if (!(h > 0 && h < 0.1)) {
        snprintf(out->message, USM_MSG_LEN, "h: must be in (0, 0.1)");
        return USM_EINPUT;
    }
    if (nnames < 0 || nnames > USM_SQUEAL_MAX_SENSITIVITIES) {
        snprintf(out->message, USM_MSG_LEN, "names: at most %d parameters",
                 USM_SQUEAL_MAX_SENSITIVITIES);
        return USM_EINPUT;
    }
    for (int k = 0; k < nnames; ++k)
        if (!names[k] || !usm_params_find(names[k])) {
            snprintf(out->message, USM_MSG_LEN, "names: unknown parameter \"%.60s\"",
                     names[k] ? names[k] : "");
            return USM_EINPUT;
        }
    const int rc = usm_squeal_locate_onset(m, p, over, value, toward, ts, x0, tol, out);
    if (rc != USM_OK || !out->found)
        return rc;
    double best = -1.0;
    for (int k = 0; k < nnames; ++k) {
        const char *name = names[k];
        usm_squeal_sensitivity *s = &out->sens[out->nsens];
        const usm_param_info *info = usm_params_find(name);
        snprintf(s->parameter, sizeof s->parameter, "%s", name);
        s->d_onset = s->elasticity = NAN;
        if (!info || strcmp(name, over) == 0)
            continue;
        ++out->nsens;
        usm_params base = *p;
        const double P = *usm_params_field(&base, info);
        const double dP = h * (P != 0.0 ? fabs(P) : 1.0);
        double on[2];
        int ok = 1;
        for (int side = 0; side < 2 && ok; ++side) {
            usm_params q = *p;
            *usm_params_field(&q, info) = P + (side ? dP : -dP);
            usm_squeal_onset o;
            /* from the orbit at the same start (x0, or rest): the shifted
               parameters' orbit is near it */
            if (usm_squeal_locate_onset(m, &q, over, value, toward, ts, x0, tol, &o) != USM_OK ||
                !o.found || strcmp(o.kind, out->kind) != 0) {
                snprintf(s->message, sizeof s->message, "%.100s",
                         o.found ? "the shifted onset is of another kind" : o.message);
                ok = 0;
            } else
                on[side] = o.value;
            out->solves += o.solves;
        }
        if (!ok)
            continue;
        s->h = dP;
        s->d_onset = (on[1] - on[0]) / (2.0 * dP);
        /* each location is good to tol of the bracket: a smaller change is not seen */
        s->resolution = tol * fabs(toward - value) / dP;
        s->elasticity = s->d_onset * P / out->value;
        if (fabs(s->elasticity) > best) {
            best = fabs(s->elasticity);
            snprintf(out->most_sensitive, sizeof out->most_sensitive, "%s", name);
        }
    }
    return USM_OK;
}
