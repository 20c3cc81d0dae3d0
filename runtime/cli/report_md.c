/* report.md: the paper's published values beside the computed ones, the
 * explanations where they differ, the figures and the files. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <string.h>

#include "report.h"

#ifndef USM_VERSION
#define USM_VERSION "unknown"
#endif

#define TWO_PI 6.283185307179586476925286766559
#define PI 3.14159265358979323846264338327950

/* ---- formatting -------------------------------------------------------------- */

/* Rotating buffers so that several formatted numbers fit in one fprintf
 * (no call below formats more than 32; the report is written by one thread). */
#define NBUF 64
static char *buf_next(void)
{
    static char bufs[NBUF][64];
    static int k;
    k = (k + 1) % NBUF;
    return bufs[k];
}

static const char *g(double v, int digits)
{
    char *b = buf_next();
    if (!isfinite(v))
        snprintf(b, 64, "n/a");
    else
        snprintf(b, 64, "%.*g", digits, v);
    return b;
}

/* Signed, e.g. "+2.3e-05". */
static const char *sg(double v, int digits)
{
    char *b = buf_next();
    if (!isfinite(v))
        snprintf(b, 64, "n/a");
    else
        snprintf(b, 64, "%+.*g", digits, v);
    return b;
}

static const char *cplx(double re, double im, int digits)
{
    char *b = buf_next();
    if (im > 0)
        snprintf(b, 64, "%.*f ± %.*fi", digits, re, digits, im);
    else if (im < 0)
        snprintf(b, 64, "%.*f ∓ %.*fi", digits, re, digits, -im);
    else
        snprintf(b, 64, "%.*f", digits, re);
    return b;
}

static const char *located(const report_located *l, double scale, int digits)
{
    return l->ok ? g(l->value * scale, digits) : "not found";
}

/* ---- sections ------------------------------------------------------------------ */

static void head(FILE *f, const report_data *d)
{
    fprintf(f,
            "%s\n"
            "# \"Modeling and stability analysis for an ultrasonic motor\", reproduced\n"
            "\n"
            "Written by `usm report` (usm %s, kernels by generator %s). Every *computed* value in "
            "this report was computed by this run through libusm (`usm_steady_*`, "
            "`usm_floquet_*`, `usm_sweep_*`). The only numbers typed into the program are the "
            "paper's published values, kept in one table "
            "(`data/paper_values.json`, installed as `share/usm/paper_values.json`). Grids: %s%s.\n"
            "\n"
            "1. [Parameters](#1-parameters)\n"
            "2. [The paper's numbers beside the computed ones](#2-the-papers-numbers-beside-the-computed-ones)\n"
            "3. [Where the model and the paper disagree, and why](#3-where-the-model-and-the-paper-disagree-and-why)\n"
            "4. [Floquet multipliers and the start time t0](#4-floquet-multipliers-and-the-start-time-t0)\n"
            "5. [Motor characteristics](#5-motor-characteristics)\n"
            "6. [Stability maps](#6-stability-maps)\n"
            "7. [Modelling variants side by side](#7-modelling-variants-side-by-side)\n"
            "8. [Files](#8-files)\n"
            "\n",
            REPORT_MARKER, USM_VERSION, USM_GENERATOR_VERSION,
            d->opt.quick ? "coarse (`--quick`)" : "full",
            d->opt.plots ? "" : ", figures not rendered");
}

static const char *param_source(const char *name)
{
    if (strcmp(name, "f") == 0)
        return "**not in the paper**: chosen, see below";
    if (strcmp(name, "M") == 0)
        return "**not in the paper**: 2 I_R / R^2, see below";
    if (strcmp(name, "mu0") == 0 || strcmp(name, "kappa") == 0)
        return "Sec. 5 text";
    return "Appendix A, Table 5";
}

static void sec_parameters(FILE *f, const report_data *d)
{
    usm_params def;
    const report_model_result *r3 = &d->model[REPORT_3DOF];
    const double dev_best = d->M_trial_dev[1];
    usm_params_default(&def);
    fputs("## 1. Parameters\n\n"
          "| parameter | value | unit | meaning | source |\n"
          "|---|---|---|---|---|\n",
          f);
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const usm_param_info *info = &usm_param_table[k];
        const double v = usm_params_get(&d->params, info), v0 = usm_params_get(&def, info);
        fprintf(f, "| `%s` | %s | %s | %s | %s |\n", info->name, g(v, 8), info->unit,
                info->description,
                v == v0 ? param_source(info->name) : "**changed** (`--set`/`--params`)");
    }
    fprintf(f,
            "\n**The two values the paper leaves out.**\n\n"
            "- **Excitation frequency f = %s Hz.** The paper never states Omega, but Appendix A "
            "is built on a %s kHz stator: sqrt(c_r / I_xx) / (2 pi) = %s Hz, i.e. "
            "c_r = I_xx (2 pi 37 kHz)^2, and both damping constants are 3 %% damping at that "
            "frequency: 2 * 0.03 * sqrt(c_r I_xx) = %s (Appendix A: d_r = 2.3865e-4) and "
            "2 * 0.03 * sqrt(c_t I_zz) = %s (d_t = 9.1232e-4). With f = 37 kHz the stationary "
            "tilt is %s rad, the paper's 0.81836e-4 to five digits; at the 36.8 kHz of Fig. 9 it "
            "would be %s rad.\n"
            "- **Rotor mass M = 2 I_R / R^2 = %s kg**, the mass of a solid-disk rotor of radius R "
            "with inertia I_R. It enters only the axial rotor dynamics, so it changes the "
            "multipliers, not the stationary solution. Largest distance between the computed "
            "multipliers (t0 = 0) and Table 3: %s for M = 0; **%s for M = 2 I_R / R^2**; %s "
            "for M = %s kg, the mass for which d_R would be 3 %% damping like d_r and d_t "
            "((d_R / 0.06)^2 / c_R).\n"
            "- mu0 = 0.3 and kappa = 20 s/m (friction law (5.2)) are given in the text of "
            "section 5, not in Table 5.\n\n",
            g(d->params.f, 6), g(d->params.f / 1000, 4), g(d->f_from_cr, 8), g(d->dr_3pct, 5),
            g(d->dt_3pct, 5), g(r3->sol.theta, 6), g(d->theta_at_fmax_paper, 4), g(d->M_disk, 5),
            g(d->M_trial_dev[0], 2), g(dev_best, 2), g(d->M_trial_dev[2], 2),
            g(d->M_from_dR, 4));
}

/* One row of the comparison table. */
static void row(FILE *f, int *n, const char *where, const char *what, const char *paper,
                const char *computed, const char *diff, const char *verdict)
{
    fprintf(f, "| %d | %s | %s | %s | %s | %s | %s |\n", ++*n, where, what, paper, computed, diff,
            verdict);
}

static void multiplier_rows(FILE *f, int *n, const char *where,
                            const report_published_multiplier *t, int nt,
                            const usm_floquet_result *r, int table4)
{
    int used[USM_MAX_NX] = {0};
    for (int k = 0; k < nt; ++k) {
        int j = report_match_multiplier(r, t[k].re, t[k].im, used);
        char what[96], paper[96], comp[128], diff[128];
        const char *verdict = "agrees";
        double mod, dl;
        if (j < 0)
            continue;
        if (t[k].im > 0) { /* the conjugate is used too */
            int jc = report_match_multiplier(r, t[k].re, -t[k].im, used);
            (void)jc;
        }
        mod = hypot(r->re[j], r->im[j]);
        dl = hypot(r->re[j] - t[k].re, fabs(r->im[j]) - t[k].im);
        snprintf(what, sizeof what, "%s", t[k].label);
        snprintf(paper, sizeof paper, "%s (abs. %s)", t[k].printed, t[k].modulus_printed);
        snprintf(comp, sizeof comp, "%s (abs. %s)%s", cplx(r->re[j], fabs(r->im[j]), 5),
                 g(mod, 5), r->cyclic[j] ? ", cyclic: exactly 1" : "");
        snprintf(diff, sizeof diff, "\\|Δλ\\| %s, Δ\\|λ\\| %s", g(dl, 2), sg(mod - t[k].modulus, 2));
        if (table4 && k == 0)
            verdict = "**differs**, (c)";
        else if (dl > 2e-3)
            verdict = "**differs**";
        row(f, n, where, what, paper, comp, diff, verdict);
    }
}

static void sec_comparison(FILE *f, const report_data *d)
{
    const report_paper *pv = &report_paper_values;
    const usm_steady_solution *s3 = &d->model[REPORT_3DOF].sol, *s4 = &d->model[REPORT_4DOF].sol;
    const double omega = TWO_PI * d->params.f;
    char comp[256], diff[256];
    int n = 0;
    fputs("## 2. The paper's numbers beside the computed ones\n\n"
          "Every number the paper publishes as a result, as printed, beside the value computed "
          "with the parameters of section 1 (multipliers: t0 = 0, the paper's convention; each "
          "published multiplier is paired with the nearest computed one). Letters refer to the "
          "explanations in section 3.\n\n"
          "| # | where | quantity | paper (as printed) | computed | difference | |\n"
          "|---|---|---|---|---|---|---|\n",
          f);
    /* section 3 */
    snprintf(comp, sizeof comp, "%s rad", g(s3->theta, 6));
    snprintf(diff, sizeof diff, "relative %s", sg(s3->theta / pv->theta3.value - 1, 2));
    row(f, &n, pv->theta3.where, pv->theta3.what, pv->theta3.printed, comp, diff, "agrees");
    snprintf(comp, sizeof comp, "%s rad", g(s3->alpha, 6));
    snprintf(diff, sizeof diff, "%s (as radians; as degrees the printed value is %s rad)",
             sg(s3->alpha - pv->alpha3.value, 3), g(pv->alpha3.value * PI / 180, 3));
    row(f, &n, pv->alpha3.where, pv->alpha3.what, pv->alpha3.printed, comp, diff,
        "misprint of 5.126 rad, (a)");
    snprintf(comp, sizeof comp, "%s rad; beta + pi = %s", g(s3->beta, 6), g(s3->beta + PI, 5));
    snprintf(diff, sizeof diff, "%s (beta + pi vs printed)", sg(s3->beta + PI - pv->beta3.value, 2));
    row(f, &n, pv->beta3.where, pv->beta3.what, pv->beta3.printed, comp, diff,
        "branch modulo pi and sign of (3.6), (a)");
    /* section 5 */
    snprintf(comp, sizeof comp, "%s 1/s", g(s4->rotor_speed, 6));
    snprintf(diff, sizeof diff, "%s", sg(s4->rotor_speed - pv->speed4.value, 2));
    row(f, &n, pv->speed4.where, pv->speed4.what, pv->speed4.printed, comp, diff, "agrees");
    snprintf(comp, sizeof comp, "%s rad", g(s4->theta, 6));
    snprintf(diff, sizeof diff, "relative %s", sg(s4->theta / pv->theta4.value - 1, 2));
    row(f, &n, pv->theta4.where, pv->theta4.what, pv->theta4.printed, comp, diff, "agrees");
    snprintf(comp, sizeof comp, "%s rad", g(s4->alpha, 6));
    snprintf(diff, sizeof diff, "%s", sg(s4->alpha - pv->alpha4.value, 2));
    row(f, &n, pv->alpha4.where, pv->alpha4.what, pv->alpha4.printed, comp, diff,
        "agrees (printed truncated)");
    snprintf(comp, sizeof comp, "%s rad", g(s4->beta, 6));
    snprintf(diff, sizeof diff, "%s", sg(s4->beta - pv->beta4.value, 2));
    row(f, &n, pv->beta4.where, pv->beta4.what, pv->beta4.printed, comp, diff,
        "agrees (printed truncated)");
    /* Tables 3 and 4 */
    multiplier_rows(f, &n, "Table 3", pv->table3, pv->n3, &d->model[REPORT_3DOF].fl[0], 0);
    multiplier_rows(f, &n, "Table 4", pv->table4, pv->n4, &d->model[REPORT_4DOF].fl[0], 1);
    snprintf(comp, sizeof comp, "3-DOF max \\|λ\\| = %s, 4-DOF %s (non-cyclic)",
             g(d->model[REPORT_3DOF].fl[0].max_modulus, 5),
             g(d->model[REPORT_4DOF].fl[0].max_modulus, 5));
    row(f, &n, "Sec. 4, 5", "stability of the stationary solution", "stable (both models)", comp,
        "", d->model[REPORT_3DOF].fl[0].stable && d->model[REPORT_4DOF].fl[0].stable
                ? "agrees" : "**differs**");
    /* Fig. 9 */
    snprintf(comp, sizeof comp, "3-DOF %s kHz, 4-DOF %s kHz", located(&d->f_max[0], 1e-3, 5),
             located(&d->f_max[1], 1e-3, 5));
    snprintf(diff, sizeof diff, "%s Hz (%s %%)",
             d->f_max[0].ok ? sg(d->f_max[0].value - pv->f_max.value, 3) : "n/a",
             d->f_max[0].ok ? sg(100 * (d->f_max[0].value / pv->f_max.value - 1), 2) : "n/a");
    row(f, &n, pv->f_max.where, pv->f_max.what, pv->f_max.printed, comp, diff,
        "**differs**, (d)");
    /* Fig. 10 */
    snprintf(comp, sizeof comp, "stick limit F_t = mu0 F_n: %s N mm", located(&d->stick_limit, 1e3, 4));
    snprintf(diff, sizeof diff, "%s N mm",
             d->stick_limit.ok ? sg((d->stick_limit.value - pv->slip_load.value) * 1e3, 3) : "n/a");
    row(f, &n, pv->slip_load.where, pv->slip_load.what, pv->slip_load.printed, comp, diff,
        "**differs**, (e)");
    snprintf(comp, sizeof comp,
             "F_t = mu0 (pi/2) F_n (the friction law's supremum): %s N mm; the 4-DOF solution "
             "exists up to %s N mm",
             located(&d->stick_limit_sat, 1e3, 4), located(&d->existence_T[REPORT_4DOF], 1e3, 4));
    snprintf(diff, sizeof diff, "%s N mm",
             d->stick_limit_sat.ok ? sg((d->stick_limit_sat.value - pv->slip_load.value) * 1e3, 3)
                                   : "n/a");
    row(f, &n, pv->slip_load.where, pv->slip_load.what, pv->slip_load.printed, comp, diff,
        "**differs**, (e)");
    snprintf(comp, sizeof comp, "the 3-DOF stick solution exists up to %s N mm",
             located(&d->existence_T[REPORT_3DOF], 1e3, 4));
    snprintf(diff, sizeof diff, "%s N mm",
             d->existence_T[0].ok ? sg((d->existence_T[0].value - pv->slip_load.value) * 1e3, 3)
                                  : "n/a");
    row(f, &n, pv->slip_load.where, pv->slip_load.what, pv->slip_load.printed, comp, diff,
        "**differs**, (e)");
    /* Sec. 6 */
    snprintf(comp, sizeof comp, "Omega / \\|phidot_R\\| = %s (3-DOF), %s (4-DOF)",
             g(omega / fabs(s3->rotor_speed), 3), g(omega / fabs(s4->rotor_speed), 3));
    snprintf(diff, sizeof diff, "same order of magnitude");
    row(f, &n, pv->speed_ratio.where, pv->speed_ratio.what, pv->speed_ratio.printed, comp, diff,
        "agrees");
    fputc('\n', f);
}

/* Largest distance between a published table and the multipliers r. */
static double table_distance(const report_published_multiplier *t, int nt,
                             const usm_floquet_result *r, int skip_first)
{
    int used[USM_MAX_NX] = {0};
    double dev = 0;
    for (int k = 0; k < nt; ++k)
        for (int sgn = 1; sgn >= (t[k].im > 0 ? -1 : 1); sgn -= 2) {
            int j = report_match_multiplier(r, t[k].re, sgn * t[k].im, used);
            if (j < 0)
                return INFINITY;
            if (!(skip_first && k == 0))
                dev = fmax(dev, hypot(r->re[j] - t[k].re, r->im[j] - sgn * t[k].im));
        }
    return dev;
}

static void sec_disagreements(FILE *f, const report_data *d)
{
    const report_paper *pv = &report_paper_values;
    const report_model_result *r3 = &d->model[REPORT_3DOF], *r4 = &d->model[REPORT_4DOF];
    const usm_floquet_result *fl4 = &r4->fl[0];
    int used[USM_MAX_NX] = {0};
    int j = report_match_multiplier(fl4, pv->table4[0].re, pv->table4[0].im, used);
    const double mod_c = j >= 0 ? hypot(fl4->re[j], fl4->im[j]) : NAN;
    const double ang_c = j >= 0 ? atan2(fabs(fl4->im[j]), fl4->re[j]) : NAN;
    const double ang_p = atan2(pv->table4[0].im, pv->table4[0].re);
    const double mu_needed =
        pv->slip_load.value / (r3->sol.R_star * r3->sol.F_n); /* F_t R* = T at the stationary state */
    double fmax_diff = d->f_max[0].ok ? d->f_max[0].value - pv->f_max.value : NAN;
    fprintf(f,
            "## 3. Where the model and the paper disagree, and why\n\n"
            "**(a) Misprints in section 3.** The phase angles are radians in [0, 2 pi): the "
            "computed alpha = %s rad is the printed \"5.16\" with two digits transposed "
            "(5.126), and \"degrees\" is wrong (5.16 degrees would be %s rad, and no stationary "
            "solution has it). (3.6) has a sign error: the twisting balance "
            "c_t (alpha + beta cos(theta)) = T gives beta = (T/c_t - alpha)/cos(theta) = %s rad; "
            "the printed -1.98 is beta + pi = %s, the same twist direction taken modulo pi. "
            "Section 5 prints the same angles as 5.12 and -5.12. (3.7) drops the sign of the "
            "rotor speed: phidot_R = %s 1/s is negative (the rotor turns against the contact "
            "point, as the paper's Fig. 8 discussion says); the small-angle formula "
            "H theta Omega / R gives %s 1/s in magnitude.\n\n",
            g(r3->sol.alpha, 5), g(pv->alpha3.value * PI / 180, 3), g(r3->sol.beta, 5),
            g(r3->sol.beta + PI, 4), g(r3->sol.rotor_speed, 5),
            g(d->params.H * r3->sol.theta * TWO_PI * d->params.f / d->params.R, 5));
    {
        const usm_floquet_result *fl = r3->fl;
        const int last = REPORT_NT0 - 1;
        fprintf(f,
                "**(b) The start time t0 of the Floquet analysis.** The paper treats the "
                "linearisation as periodic. Under its twist law (the twisting torque "
                "c_t (phi + psi cos(theta))) one entry of the linearisation, "
                "-c_t psi(t) sin(theta), grows linearly in time with psi, so the monodromy "
                "matrix depends on the start t0 of the period, the more the later it starts: "
                "the largest 3-DOF modulus is %s from t0 = 0, %s from %s and %s from %s%s. "
                "**Table 3 uses t0 = 0**: it is the start time closest to the table (largest "
                "distance %s, against %s from t0 = %s, %s from %s and %s from %s). All "
                "multipliers in section 2 use t0 = 0.",
                g(fl[0].max_modulus, 5), g(fl[4].max_modulus, 5), report_t0_label[4],
                g(fl[last].max_modulus, 5), report_t0_label[last],
                fl[last].stable ? "" : ": from there the same stationary solution would be "
                                       "called unstable",
                g(table_distance(pv->table3, pv->n3, &fl[0], 0), 2),
                g(table_distance(pv->table3, pv->n3, &fl[1], 0), 2), report_t0_label[1],
                g(table_distance(pv->table3, pv->n3, &fl[2], 0), 2), report_t0_label[2],
                g(table_distance(pv->table3, pv->n3, &fl[3], 0), 2), report_t0_label[3]);
        if (r3->integrated)
            fprintf(f,
                    " Integrating the twist angle from omega_Z instead (variant "
                    "`twist_integrated`, one more state) removes the dependence: the same "
                    "multipliers from t0 = 0 and T/2 (largest modulus %s and %s), within %s "
                    "of Table 3.",
                    g(r3->fl_integrated[0].max_modulus, 6), g(r3->fl_integrated[1].max_modulus, 6),
                    g(table_distance(pv->table3, pv->n3, &r3->fl_integrated[0], 0), 2));
        fputs("\n\n", f);
    }
    fprintf(f,
            "**(c) Table 4's first pair.** The paper prints 0.2616 ± 0.4934i (abs. 0.5585); the "
            "model gives %s (abs. %s): the same angle (%s vs %s rad) but a modulus %s %% larger. "
            "Every other multiplier of Tables 3 and 4 agrees to %s with the same "
            "parameters; the cause of this one difference is not known (a misprint in Table 4, "
            "or a difference in the paper's computation).\n\n",
            j >= 0 ? cplx(fl4->re[j], fabs(fl4->im[j]), 4) : "n/a", g(mod_c, 4), g(ang_c, 4),
            g(ang_p, 4), g(100 * (mod_c / pv->table4[0].modulus - 1), 2),
            g(fmax(table_distance(pv->table3, pv->n3, &r3->fl[0], 0),
                   table_distance(pv->table4, pv->n4, fl4, 1)), 1));
    fprintf(f,
            "**(d) Fig. 9, the speed maximum.** The paper places it \"near an eigenfrequency of "
            "the stator at 36.8 kHz\". With the parameters that reproduce the stationary "
            "solution and Tables 3 and 4, the undamped tilt eigenfrequency sqrt(c_r/I_xx)/(2 pi) "
            "is %s kHz; the tilt peaks at %s kHz and the rotor speed, proportional to "
            "Omega tan(theta), at %s kHz (3-DOF; 4-DOF %s kHz): %s Hz from the paper's value. "
            "The peak lies above the eigenfrequency because the excitation must first "
            "overcome the contact moment F_n R* (%s mN m, against m0 = %s mN m); with a "
            "preload of only F0 = %g N the tilt would peak at %s kHz, at the damped "
            "eigenfrequency. At 36.8 kHz the tilt "
            "would be %s rad, not the published 0.81836e-4, so the paper's Fig. 9 cannot come "
            "from the parameters of its tables.\n\n",
            g(d->f_from_cr / 1000, 6), located(&d->f_theta_max, 1e-3, 5),
            located(&d->f_max[0], 1e-3, 5), located(&d->f_max[1], 1e-3, 5), sg(fmax_diff, 3),
            g(r3->sol.F_n * r3->sol.R_star * 1e3, 3), g(d->params.m0 * 1e3, 3), REPORT_SMALL_F0,
            located(&d->f_theta_max_small_F0, 1e-3, 5), g(d->theta_at_fmax_paper, 4));
    fprintf(f,
            "**(e) Fig. 10, \"above a load of 9.7 Nmm slip will occur\".** Nothing in the model "
            "happens at 9.7 N mm. At the stationary state the rotor balance is F_t R* = T, so "
            "the friction the stick model needs grows with the load: F_t = mu0 F_n (mu0 = %s) "
            "is reached at T = %s N mm, and the friction law's supremum mu0 pi/2 at %s N mm, "
            "where the 4-DOF slip solution stops existing (%s N mm). The 3-DOF stick solution, "
            "which ignores the friction limit, exists up to %s N mm, where the tilt falls to "
            "zero. Holding 9.7 N mm would need mu = T / (R* F_n) = %s with F_n = %s N. So the "
            "9.7 N mm cannot come from these parameters.\n\n",
            g(d->params.mu0, 3), located(&d->stick_limit, 1e3, 4),
            located(&d->stick_limit_sat, 1e3, 4), located(&d->existence_T[REPORT_4DOF], 1e3, 4),
            located(&d->existence_T[REPORT_3DOF], 1e3, 4), g(mu_needed, 3), g(r3->sol.F_n, 4));
    fprintf(f,
            "**(f) \"If a steady state solution exists this solution is always stable.\"** "
            "True for the 4-DOF model on the maps of section 6 and for the 3-DOF model wherever "
            "its stick condition holds. The 3-DOF stick model, continued beyond the stick "
            "limit where it no longer describes the motor, loses stability at T = %s N mm "
            "(largest |lambda| reaches 1; section 5).\n\n",
            located(&d->stability_T, 1e3, 4));
}

/* The multipliers, a conjugate pair as "a ± bi". */
static void mult_list(FILE *f, const usm_floquet_result *r)
{
    for (int k = 0; k < r->n; ++k) {
        const int pair = r->im[k] > 0 && k + 1 < r->n && r->im[k + 1] == -r->im[k] &&
                         r->re[k + 1] == r->re[k];
        if (k)
            fputs(", ", f);
        if (pair)
            fputs(cplx(r->re[k], r->im[k], 4), f);
        else if (r->im[k] != 0)
            fprintf(f, "%.4f %c %.4fi", r->re[k], r->im[k] < 0 ? '-' : '+', fabs(r->im[k]));
        else
            fprintf(f, "%.4f", r->re[k]);
        if (r->cyclic[k])
            fputs(" (cyclic)", f);
        k += pair;
    }
}

static void figure(FILE *f, int fig, const report_data *d)
{
    const report_figure *rf = &report_figures[fig];
    if (d->opt.plots)
        fprintf(f, "![%s](%s.png)\n\n*%s.* Vector version: [%s.svg](%s.svg); data and script: "
                   "`%s.gp` and the CSV files it names.\n\n",
                rf->title, rf->name, rf->title, rf->name, rf->name, rf->name);
    else
        fprintf(f, "*%s*: not rendered; run `gnuplot %s.gp` in this directory "
                   "to draw %s.png and %s.svg.\n\n",
                rf->title, rf->name, rf->name, rf->name);
}

static void sec_floquet(FILE *f, const report_data *d)
{
    const report_paper *pv = &report_paper_values;
    fputs("## 4. Floquet multipliers and the start time t0\n\n"
          "The monodromy matrix over [t0, t0 + T], T = 2 pi / Omega, of the linearisation "
          "about the stationary solution (paper (4.9)); its eigenvalues are the multipliers. "
          "Filled dots: t0 = 0; crosses: the paper's table; open symbols: other start "
          "times.\n\n",
          f);
    figure(f, REPORT_FIG_MULT_3DOF, d);
    figure(f, REPORT_FIG_MULT_4DOF, d);
    fputs("**The t0 dependence.** Under the paper's twist law the multipliers depend on t0 "
          "(see (b) in section 3). The paper's tables correspond to t0 = 0:\n\n"
          "| model | t0 | multipliers (by decreasing modulus) | max \\|λ\\| | largest distance to the paper's table |\n"
          "|---|---|---|---|---|\n",
          f);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        const report_model_result *r = &d->model[k];
        const report_published_multiplier *t = k == REPORT_3DOF ? pv->table3 : pv->table4;
        const int nt = k == REPORT_3DOF ? pv->n3 : pv->n4;
        for (int i = 0; i < REPORT_NT0; ++i) {
            fprintf(f, "| %s | %s | ", r->model->name, report_t0_label[i]);
            mult_list(f, &r->fl[i]);
            fprintf(f, " | %s | %s%s |\n", g(r->fl[i].max_modulus, 5),
                    g(table_distance(t, nt, &r->fl[i], k == REPORT_4DOF), 2),
                    k == REPORT_4DOF ? " (without the first pair, see (c))" : "");
        }
        for (int i = 0; r->integrated && i < 2; ++i) {
            fprintf(f, "| %s, twist integrated | %s | ", r->model->name, i ? "T/2" : "0");
            mult_list(f, &r->fl_integrated[i]);
            fprintf(f, " | %s | %s%s |\n", g(r->fl_integrated[i].max_modulus, 5),
                    g(table_distance(t, nt, &r->fl_integrated[i], k == REPORT_4DOF), 2),
                    k == REPORT_4DOF ? " (without the first pair, see (c))" : "");
        }
    }
    {
        int unstable = 0, total = 0;
        for (int k = 0; k < REPORT_NMODELS; ++k)
            for (int i = 0; i < REPORT_NT0; ++i) {
                ++total;
                unstable += !d->model[k].fl[i].stable;
            }
        fprintf(f,
                "\nt0 = 0 is closest to the paper's tables. Near t0 = 0 the dependence is "
                "small (the growing entry carries the factor sin(theta) ~ 1e-4), but it grows "
                "with t0 without bound: %d of these %d start times give the verdict "
                "\"unstable\" for the same stationary solution.",
                unstable, total);
    }
    if (d->model[0].integrated)
        fputs(" The variant `twist_integrated` (twist angle integrated from omega_Z) gives the "
              "same multipliers from every t0: the dependence is an artefact of the twist "
              "angle phi + psi cos(theta), whose rate is not omega_Z.",
              f);
    fputs("\n\n", f);
}

static void events_table(FILE *f, const report_data *d)
{
    static const char *const cname[REPORT_NCURVES] = {"f [Hz]", "T [N m]", "m0 [N m]"};
    fputs("Events the sweeps (`usm_sweep_run`, pseudo-arclength continuation) located along "
          "the curves:\n\n"
          "| curve | model | event | at | what changes |\n"
          "|---|---|---|---|---|\n",
          f);
    for (int c = 0; c < REPORT_NCURVES; ++c)
        for (int k = 0; k < REPORT_NMODELS; ++k) {
            const usm_sweep *sw = d->curve[c][k].sweep;
            const size_t n = sw ? usm_sweep_event_count(sw) : 0;
            for (size_t i = 0; i < n; ++i) {
                const usm_sweep_event *e = usm_sweep_event_at(sw, i);
                char what[USM_MSG_LEN];
                snprintf(what, sizeof what, "%s", e->what);
                fprintf(f, "| %s | %s | %s | %s | ", cname[c], d->model[k].model->name,
                        usm_event_name(e->type), g(e->value, 6));
                for (const char *p = what; *p; ++p)
                    if (*p == '|')
                        fputs("\\|", f);
                    else
                        fputc(*p == '\n' ? ' ' : *p, f);
                fputs(" |\n", f);
            }
            if (n == 0)
                fprintf(f, "| %s | %s | none | | |\n", cname[c], d->model[k].model->name);
        }
    fputc('\n', f);
}

/* The first event of `type` on a curve, or NULL. */
static const usm_sweep_event *find_event(const report_curve *cv, usm_event_type type)
{
    const size_t n = cv->sweep ? usm_sweep_event_count(cv->sweep) : 0;
    for (size_t i = 0; i < n; ++i)
        if (usm_sweep_event_at(cv->sweep, i)->type == type)
            return usm_sweep_event_at(cv->sweep, i);
    return NULL;
}

/* The key numbers located by bisection beside the sweep's own events. */
static void cross_check(FILE *f, const report_data *d)
{
    const struct {
        const report_located *l;
        int curve, model;
        usm_event_type type;
    } pairs[] = {
        {&d->stick_limit, REPORT_CURVE_T, REPORT_3DOF, USM_EVENT_STICK_LIMIT},
        {&d->stability_T, REPORT_CURVE_T, REPORT_3DOF, USM_EVENT_STABILITY_CHANGE},
        {&d->existence_T[REPORT_3DOF], REPORT_CURVE_T, REPORT_3DOF, USM_EVENT_FOLD},
        {&d->existence_T[REPORT_4DOF], REPORT_CURVE_T, REPORT_4DOF, USM_EVENT_FRICTION_SATURATION},
        {&d->existence_m0[REPORT_3DOF], REPORT_CURVE_M0, REPORT_3DOF, USM_EVENT_FOLD},
        {&d->existence_m0[REPORT_4DOF], REPORT_CURVE_M0, REPORT_4DOF, USM_EVENT_FOLD},
    };
    double worst = 0;
    int compared = 0, missing = 0;
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; ++k) {
        const usm_sweep_event *e = find_event(&d->curve[pairs[k].curve][pairs[k].model], pairs[k].type);
        if (!pairs[k].l->ok || !e) {
            ++missing;
            continue;
        }
        ++compared;
        worst = fmax(worst, fabs(e->value - pairs[k].l->value) / fabs(pairs[k].l->value));
    }
    fprintf(f,
            "Cross-check: the %d limits above that the sweeps also report as events agree with "
            "them to a relative %s%s.\n\n",
            compared, g(worst, 2),
            missing ? " (the sweeps did not report the others)" : "");
}

static void sec_characteristics(FILE *f, const report_data *d)
{
    const report_located *fm = d->f_max;
    fprintf(f,
            "## 5. Motor characteristics\n\n"
            "Sweeps of one parameter from the paper's operating point (Appendix A), both "
            "models, by continuation of the stationary solution (`usm_sweep_run`, %d to %d "
            "points per curve). The speed shown is the rotor's speed in its driving direction, "
            "w_R = -phidot_R.\n\n",
            d->curve[REPORT_CURVE_T][REPORT_4DOF].points, d->curve[REPORT_CURVE_F][0].points);
    figure(f, REPORT_FIG_SPEED_F, d);
    figure(f, REPORT_FIG_SPEED_T, d);
    figure(f, REPORT_FIG_SPEED_M0, d);
    fprintf(f,
            "**Key numbers** (located from the sweeps' grid by golden section for maxima and "
            "bisection for limits, each step a full stationary search, `usm_steady_solve`):\n\n"
            "| quantity | 3-DOF (stick) | 4-DOF (slip) | paper |\n"
            "|---|---|---|---|\n"
            "| frequency of the speed maximum [kHz] | %s (w_R = %s 1/s) | %s (w_R = %s 1/s) | near 36.8 |\n"
            "| frequency of the tilt maximum [kHz] | %s (theta = %s rad) | same stator | |\n"
            "| stick limit F_t = mu0 F_n [N mm] | %s (w_R = %s 1/s) | same stator equations | slip above 9.7 |\n"
            "| F_t = mu0 (pi/2) F_n [N mm] | %s | | |\n"
            "| largest load with a stationary solution [N mm] | %s (theta = %s rad there) | %s (friction saturated) | |\n"
            "| load where the largest \\|λ\\| reaches 1 [N mm] | %s | stable where it exists | always stable |\n"
            "| smallest m0 with a stationary solution [mN m] | %s | %s | |\n\n"
            "Below the smallest m0 the excitation cannot hold any tilt: there the tilt goes "
            "to zero, and m0 equals the moment of the contact force about the tilt axis, "
            "F_n R* = %s mN m.\n\n",
            located(&fm[0], 1e-3, 6), fm[0].ok ? g(-fm[0].sol.rotor_speed, 5) : "n/a",
            located(&fm[1], 1e-3, 6), fm[1].ok ? g(-fm[1].sol.rotor_speed, 5) : "n/a",
            located(&d->f_theta_max, 1e-3, 6), d->f_theta_max.ok ? g(d->f_theta_max.sol.theta, 5) : "n/a",
            located(&d->stick_limit, 1e3, 5),
            d->stick_limit.ok ? g(-d->stick_limit.sol.rotor_speed, 4) : "n/a",
            located(&d->stick_limit_sat, 1e3, 5), located(&d->existence_T[0], 1e3, 5),
            d->existence_T[0].ok ? g(d->existence_T[0].sol.theta, 3) : "n/a",
            located(&d->existence_T[1], 1e3, 5), located(&d->stability_T, 1e3, 5),
            located(&d->existence_m0[0], 1e3, 5), located(&d->existence_m0[1], 1e3, 5),
            d->existence_m0[0].ok
                ? g(d->existence_m0[0].sol.F_n * d->existence_m0[0].sol.R_star * 1e3, 5)
                : "n/a");
    events_table(f, d);
    cross_check(f, d);
}

static void map_summary(FILE *f, const report_map *m)
{
    const size_t n = (size_t)m->x.points * (size_t)m->y.points;
    size_t exist = 0, unstable = 0, unstable_stick = 0;
    double maxmod = 0, maxmod_stick = 0;
    for (size_t q = 0; q < n; ++q) {
        const report_map_cell *c = &m->cells[q];
        if (!c->exists)
            continue;
        ++exist;
        if (c->floquet_ok) {
            maxmod = fmax(maxmod, c->max_modulus);
            unstable += !c->stable;
            if (c->stick_admissible) {
                maxmod_stick = fmax(maxmod_stick, c->max_modulus);
                unstable_stick += !c->stable;
            }
        }
    }
    fprintf(f,
            "%s model, %d x %d grid (f from %s to %s kHz, T from %s to %s N mm): a stationary "
            "solution exists at %zu of %zu points; %zu of them unstable (largest |λ| %s); "
            "where F_t <= mu0 F_n, %zu unstable (largest |λ| %s).%s\n\n",
            m->model->name, m->x.points, m->y.points, g(m->x.from / 1000, 4), g(m->x.to / 1000, 4),
            g(m->y.from * 1e3, 3), g(m->y.to * 1e3, 3), exist, n, unstable, g(maxmod, 4),
            unstable_stick, g(maxmod_stick, 4),
            m->floquet_failures ? " (The Floquet computation failed at some points: shown grey.)"
                                : "");
}

static void sec_maps(FILE *f, const report_data *d)
{
    fputs("## 6. Stability maps\n\n"
          "The largest non-cyclic Floquet multiplier modulus (t0 = 0) of the primary "
          "stationary solution over excitation frequency f and load torque T, each grid point "
          "solved from scratch (`usm_steady_solve`, `usm_floquet_compute`; the points are "
          "shared among threads). Grey: no stationary solution. Lines: where, along T, the "
          "solution stops existing (black), |λ| crosses 1 (white, dashed) and F_t = mu0 F_n "
          "(green), each located by bisection. The same map for any two parameters: "
          "`usm map --x NAME ... --y NAME ...`.\n\n",
          f);
    for (int k = 0; k < REPORT_NMODELS; ++k) {
        if (!d->have_map[k])
            continue;
        figure(f, k == REPORT_3DOF ? REPORT_FIG_MAP_3DOF : REPORT_FIG_MAP_4DOF, d);
        map_summary(f, &d->map[k]);
    }
}

static void sec_variants(FILE *f, const report_data *d)
{
    fputs("## 7. Modelling variants side by side\n\n"
          "Every generated model (`usm variants`; derive/variants.py) at the parameters of "
          "section 1: the paper's assumptions and the alternatives. The largest non-cyclic "
          "multiplier modulus is given from three start times t0 of the Floquet period; under "
          "the paper's twist law it depends on t0, under the integrated twist law it does "
          "not. Select a variant with `--variant NAME` in `usm steady`, `sweep`, `map` and "
          "`simulate`.\n\n"
          "| model | assumptions | theta [rad] | rotor speed [1/s] | v_rel [m/s] | max \\|λ\\| "
          "(t0 = 0) | (t0 = T/2) | (t0 = 100 T) | multipliers depend on t0 |\n"
          "|---|---|---|---|---|---|---|---|---|\n",
          f);
    for (int k = 0; k < USM_NMODELS; ++k) {
        const report_variant_result *v = &d->variant[k];
        fprintf(f, "| `%s` | %s | ", v->model->name, v->model->assumptions);
        if (!v->ok) {
            fprintf(f, "no stationary solution: %s | | | | | | |\n", v->note);
            continue;
        }
        fprintf(f, "%s | %s | %s | ", g(v->sol.theta, 6), g(v->sol.rotor_speed, 6),
                g(v->sol.v_rel, 4));
        for (int i = 0; i < REPORT_NVARIANT_T0; ++i)
            fprintf(f, "%s | ", g(v->fl[i].max_modulus, 6));
        fprintf(f, "%s |\n", v->fl[0].t0_dependent ? "yes" : "no");
    }
    fputs("\nThe stationary solution itself does not depend on the twist law (the twist "
          "angle enters only the Z row, which fixes beta) nor, in theta, on the friction law "
          "(the stator sees F_t = T/R* on any stationary solution); the friction law sets the "
          "slip velocity and so the rotor speed of the slip model.\n\n",
          f);
}

static void sec_files(FILE *f, const report_data *d)
{
    fputs("## 8. Files\n\n"
          "Everything is in this directory. Each figure `NAME` has `NAME.png`, `NAME.svg`, the "
          "gnuplot script `NAME.gp` and its CSV data (header line, SI units, `nan` where a "
          "value does not exist). To re-plot: `cd` here and run `gnuplot NAME.gp`. To "
          "recompute: `usm report --out DIR` (it overwrites a report it wrote itself and "
          "refuses any other report.md without `--force`).\n\n"
          "| figure | files |\n|---|---|\n",
          f);
    for (int i = 0; i < REPORT_NFIGURES; ++i) {
        const char *name = report_figures[i].name;
        fprintf(f, "| %s | ", report_figures[i].title);
        for (int k = 0; report_files[k]; ++k)
            if (strncmp(report_files[k], name, strlen(name)) == 0 &&
                report_files[k][strlen(name)] != '\0' &&
                (report_files[k][strlen(name)] == '.' || report_files[k][strlen(name)] == '_'))
                fprintf(f, "`%s` ", report_files[k]);
        fputs("|\n", f);
    }
    fprintf(f,
            "\nComputed with %d thread(s) in %s s: stationary solutions and multipliers %s s, "
            "characteristic curves %s s, stability maps %s s, figures %s s.\n",
            d->opt.threads, g(d->seconds[0] + d->seconds[1] + d->seconds[2] + d->seconds[3], 3),
            g(d->seconds[0], 2), g(d->seconds[1], 2), g(d->seconds[2], 2), g(d->seconds[3], 2));
}

int report_write_md(const report_data *d, int plots_ok, const char *plot_note, FILE *out)
{
    head(out, d);
    if (!plots_ok && plot_note && plot_note[0])
        fprintf(out, "> **Figures missing:** %s\n\n", plot_note);
    sec_parameters(out, d);
    sec_comparison(out, d);
    sec_disagreements(out, d);
    sec_floquet(out, d);
    sec_characteristics(out, d);
    sec_maps(out, d);
    sec_variants(out, d);
    sec_files(out, d);
    return ferror(out) ? -1 : 0;
}
