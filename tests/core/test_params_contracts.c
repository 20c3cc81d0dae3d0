/* The generated contracts (generated/usm_contracts.h) against independent truth.
 *
 * - Parameters: the list below is written from the documents (docs/cli.md's
 *   parameter table, docs/periodic.md's imperfections), each entry naming the
 *   enumerator, the usm_params field and the unit.  USM_P_<name> must give the
 *   table row of that name and unit, whose offset is the field's; docs/cli.md
 *   (read at run time, argv[1]) must state the same unit and constraint; the
 *   column USM_P_<name> of steady_jacobian_params must be the derivative in the
 *   field <name> (central differences in the field offsetof finds).
 * - Outputs: names and units as docs/cli.md's JSON keys state them; R* and Z
 *   (docs/derivation.md: R* = R cos(theta) - H sin(theta),
 *   Z = R sin(theta) + H cos(theta)) at the indices USM_OUT_R_STAR, USM_OUT_Z,
 *   USM_STEADY_R_STAR and USM_STEADY_Z.
 * - Couplings: a model assuming an axisymmetric stator (its assumptions
 *   string) ties I_yy to I_xx and nothing else; its kernels do not read I_yy
 *   (changing it changes no output bit) but do read I_xx; usm_params_couple
 *   makes I_yy equal I_xx, after which usm_params_check accepts the point,
 *   and refuses I_yy != I_xx naming both.
 * - Offsets of packed outputs (usm_model.<kernel>_out, usm_unilateral's, and
 *   each header's <MODEL>_<KERNEL>_OUT_<BLOCK>): every block read at its
 *   offset against a second computation: linearisation's blocks against the
 *   separate kernels mass, jac_rhs and jac_mass; steady_state's rate and
 *   floquet_direction's blocks (along dt) against central differences in t;
 *   steady_design_jacobian's blocks against central differences of
 *   steady_outputs and steady_power in u and in the load T; friction's slope
 *   against differences of mu; the unilateral guards, contact velocity and
 *   separation against their definitions (gap = Z_R - Z, F_n of outputs,
 *   y = (x, ...)), the impacts against Newton's law at the contact.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "usm.h"
#include "usm_3dof.h"
#include "usm_4dof_imperfect_unilateral.h"
#include "usm_tolerance.h"

typedef struct expected {
    int index;       /* the enumerator */
    const char *name;
    const char *unit;
    size_t offset;   /* offsetof(usm_params, field) */
} expected;

#define E(field, unit) {USM_P_##field, #field, unit, offsetof(usm_params, field)}
/* docs/cli.md "Parameters", docs/periodic.md (e dimensionless, delta in rad, s dimensionless)
 * and docs/unilateral.md (e_impact dimensionless) */
static const expected params[] = {
    E(m0, "N m"),        E(T, "N m"),         E(F0, "N"),           E(c_R, "N/m"),
    E(d_R, "N s/m"),     E(c_t, "N m/rad"),   E(c_r, "N m/rad"),    E(d_t, "N m s/rad"),
    E(d_r, "N m s/rad"), E(R, "m"),           E(H, "m"),            E(I_R, "kg m^2"),
    E(I_xx, "kg m^2"),   E(I_yy, "kg m^2"),   E(I_zz, "kg m^2"),    E(M, "kg"),
    E(f, "Hz"),          E(mu0, "1"),         E(kappa, "s/m"),      E(amp_imbalance, "1"),
    E(phase_error, "rad"), E(mode_split, "1"), E(e_impact, "1"),
};
#define NEXP ((int)(sizeof params / sizeof params[0]))

static const expected *by_name(const char *name)
{
    for (int i = 0; i < NEXP; ++i)
        if (strcmp(params[i].name, name) == 0)
            return &params[i];
    return NULL;
}

static char *trim(char *s)
{
    while (*s == ' ' || *s == '`')
        ++s;
    char *e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '`' || e[-1] == '\n'))
        *--e = '\0';
    return s;
}

/* docs/cli.md: | `name` | unit | default | meaning | constraint | */
static void check_documented(const char *path)
{
    FILE *f = fopen(path, "r");
    CHECK(f != NULL, "cannot read %s", path);
    if (!f)
        return;
    char line[1024];
    int in_table = 0, rows = 0;
    while (fgets(line, sizeof line, f)) {
        static const char header[] = "| name | unit | default | meaning | constraint |";
        if (strncmp(line, header, sizeof header - 1) == 0) {
            in_table = 1;
            continue;
        }
        if (!in_table || strncmp(line, "|---", 4) == 0)
            continue;
        if (line[0] != '|')
            break;
        char *cell[7] = {0};
        int n = 0;
        for (char *tok = strtok(line + 1, "|"); tok && n < 7; tok = strtok(NULL, "|"))
            cell[n++] = trim(tok);
        CHECK(n >= 5, "docs table row with %d cells", n);
        if (n < 5)
            continue;
        ++rows;
        const expected *e = by_name(cell[0]);
        CHECK(e != NULL, "%s: documented, not in the test's list", cell[0]);
        if (!e)
            continue;
        const usm_param_info *info = &usm_param_table[e->index];
        CHECK(strcmp(info->name, cell[0]) == 0, "USM_P_%s gives the row of %s", cell[0],
              info->name);
        CHECK(strcmp(info->unit, cell[1]) == 0, "%s: unit %s, documented %s", cell[0], info->unit,
              cell[1]);
        const usm_constraint c = usm_param_constraints[e->index];
        const usm_constraint doc = strncmp(cell[4], ">= 0", 4) == 0  ? USM_CONSTRAINT_NONNEGATIVE
                                   : strncmp(cell[4], "> 0", 3) == 0 ? USM_CONSTRAINT_POSITIVE
                                   : strcmp(cell[4], "any") == 0     ? USM_CONSTRAINT_ANY
                                                                     : USM_CONSTRAINT_COUNT;
        CHECK(c == doc, "%s: constraint %d, documented \"%s\"", cell[0], (int)c, cell[4]);
        /* the range column: "LO .. HI" in SI */
        char *dots = n >= 6 ? strstr(cell[5], "..") : NULL;
        CHECK(dots != NULL, "%s: no documented range", cell[0]);
        if (dots) {
            const double lo = strtod(cell[5], NULL), hi = strtod(dots + 2, NULL);
            const usm_param_range *r = &usm_param_ranges[e->index];
            CHECK(lo == r->lo && hi == r->hi, "%s: range %g .. %g, documented %g .. %g",
                  cell[0], r->lo, r->hi, lo, hi);
        }
    }
    fclose(f);
    CHECK(rows == 19, "docs/cli.md: %d parameter rows, expected the 19 of the ideal motor", rows);
}

static void check_params(void)
{
    CHECK(USM_P_COUNT == USM_NPARAMS && NEXP == USM_NPARAMS, "USM_P_COUNT %d, USM_NPARAMS %d, "
          "the documents %d", (int)USM_P_COUNT, USM_NPARAMS, NEXP);
    int seen[USM_NPARAMS] = {0};
    for (int i = 0; i < NEXP; ++i) {
        const expected *e = &params[i];
        CHECK(e->index >= 0 && e->index < USM_NPARAMS, "USM_P_%s = %d", e->name, e->index);
        if (e->index < 0 || e->index >= USM_NPARAMS)
            continue;
        ++seen[e->index];
        const usm_param_info *info = &usm_param_table[e->index];
        CHECK(strcmp(info->name, e->name) == 0, "USM_P_%s gives %s", e->name, info->name);
        CHECK(strcmp(info->unit, e->unit) == 0, "%s: unit %s, documents %s", e->name, info->unit,
              e->unit);
        CHECK(info->offset == e->offset, "%s: offset %zu, field at %zu", e->name, info->offset,
              e->offset);
        CHECK(usm_params_find(e->name) == info, "usm_params_find(%s)", e->name);
        CHECK(usm_param_index(info) == e->index, "usm_param_index(%s)", e->name);
        const usm_constraint c = usm_param_constraints[e->index];
        CHECK(c >= 0 && c < USM_CONSTRAINT_COUNT &&
                  strcmp(usm_constraint_names[c], info->constraint) == 0,
              "%s: constraint %d vs \"%s\"", e->name, (int)c, info->constraint);
    }
    for (int k = 0; k < USM_NPARAMS; ++k)
        CHECK(seen[k] == 1, "index %d named %d times", k, seen[k]);
    /* the imperfections (docs/periodic.md), in table order */
    CHECK(USM_NIMPERFECTIONS == 3 && usm_param_imperfections[0] == USM_P_amp_imbalance &&
              usm_param_imperfections[1] == USM_P_phase_error &&
              usm_param_imperfections[2] == USM_P_mode_split,
          "imperfections");
    /* the words of the constraints */
    CHECK(strcmp(usm_constraint_names[USM_CONSTRAINT_POSITIVE], "positive") == 0 &&
              strcmp(usm_constraint_names[USM_CONSTRAINT_NONNEGATIVE], "nonnegative") == 0 &&
              strcmp(usm_constraint_names[USM_CONSTRAINT_ANY], "any") == 0,
          "constraint names");
}

/* The field an entry names, found by the compiler's offsetof (not the table's). */
static double *field(usm_params *p, const expected *e) { return (double *)((char *)p + e->offset); }

/* Column USM_P_<field> of steady_jacobian_params vs central differences in
 * the field <field> itself (the 19 parameters of the ideal motor). */
static void check_columns(const usm_model *m)
{
    usm_params p;
    usm_params_default(&p);
    double u[USM_MAX_NU], seed[USM_SEED_COUNT], J[USM_MAX_NU * USM_NPARAMS];
    m->steady_seed(0.01, &p, seed);
    u[m->u_theta] = 0.01;
    u[m->u_alpha] = atan2(seed[USM_SEED_SIN_ALPHA], seed[USM_SEED_COS_ALPHA]);
    if (m->u_phidot_R >= 0)
        u[m->u_phidot_R] = -200.0;
    m->steady_jacobian_params(u, &p, J);
    for (int e = 0; e < NEXP; ++e) {
        const expected *x = &params[e];
        if (x->index >= USM_P_amp_imbalance) /* the stationary kernels are the ideal motor's */
            continue;
        usm_params a = p, b = p;
        const double v = *field(&p, x), h = 1e-6 * (v != 0 ? fabs(v) : 1.0);
        double ra[USM_MAX_NU], rb[USM_MAX_NU];
        *field(&a, x) += h;
        *field(&b, x) -= h;
        m->steady_residual(u, &a, ra);
        m->steady_residual(u, &b, rb);
        for (int i = 0; i < m->nu; ++i) {
            /* the size of the row's terms J_ik p_k sets the scale of the error */
            double scale = 0;
            for (int k = 0; k < NEXP; ++k)
                scale = fmax(scale, fabs(J[i * USM_NPARAMS + params[k].index] *
                                         *field(&p, &params[k])));
            const double fd = (ra[i] - rb[i]) / (2 * h), an = J[i * USM_NPARAMS + x->index];
            CHECK(fabs(fd - an) * (v != 0 ? fabs(v) : 1.0) <= 1e-6 * scale,
                  "%s row %d column USM_P_%s: %.9g, differences %.9g", m->name, i, x->name, an,
                  fd);
        }
    }
}

static void check_outputs(void)
{
    static const struct {
        const usm_output_info *table;
        int index;
        const char *name, *unit;
    } want[] = {
        /* docs/cli.md, JSON output: rotor_speed [1/s], F_n, F_t [N], v_c, v_rel [m/s],
           beta [rad]; R*, Z lengths, powers in W, the seed's cos/sin and mismatch pure numbers */
        {usm_out_outputs, USM_OUT_R_STAR, "R_star", "m"},
        {usm_out_outputs, USM_OUT_Z, "Z", "m"},
        {usm_out_outputs, USM_OUT_V_C, "v_c", "m/s"},
        {usm_out_outputs, USM_OUT_F_N, "F_n", "N"},
        {usm_out_outputs, USM_OUT_F_T, "F_t", "N"},
        {usm_out_outputs, USM_OUT_V_REL, "v_rel", "m/s"},
        {usm_out_outputs, USM_OUT_ROTOR_SPEED, "rotor_speed", "1/s"},
        {usm_steady_outputs, USM_STEADY_BETA, "beta", "rad"},
        {usm_steady_outputs, USM_STEADY_ROTOR_SPEED, "rotor_speed", "1/s"},
        {usm_steady_outputs, USM_STEADY_F_N, "F_n", "N"},
        {usm_steady_outputs, USM_STEADY_F_T, "F_t", "N"},
        {usm_steady_outputs, USM_STEADY_V_C, "v_c", "m/s"},
        {usm_steady_outputs, USM_STEADY_V_REL, "v_rel", "m/s"},
        {usm_steady_outputs, USM_STEADY_R_STAR, "R_star", "m"},
        {usm_steady_outputs, USM_STEADY_Z, "Z", "m"},
        {usm_steady_outputs, USM_STEADY_TWIST, "twist", "rad"},
        {usm_seed_outputs, USM_SEED_AMPLITUDE_MISMATCH, "amplitude_mismatch", "1"},
        {usm_seed_outputs, USM_SEED_COS_ALPHA, "cos_alpha", "1"},
        {usm_seed_outputs, USM_SEED_SIN_ALPHA, "sin_alpha", "1"},
        {usm_seed_outputs, USM_SEED_F_T, "F_t", "N"},
        {usm_seed_outputs, USM_SEED_F_N, "F_n", "N"},
        {usm_power_outputs, USM_POWER_POWER_IN, "power_in", "W"},
        {usm_power_outputs, USM_POWER_POWER_OUT, "power_out", "W"},
        {usm_power_outputs, USM_POWER_POWER_DAMPING, "power_damping", "W"},
        {usm_power_outputs, USM_POWER_POWER_SLIP, "power_slip", "W"},
        {usm_design_outputs, USM_DESIGN_ROTOR_SPEED, "rotor_speed", "1/s"},
        {usm_design_outputs, USM_DESIGN_F_N, "F_n", "N"},
        {usm_design_outputs, USM_DESIGN_F_T, "F_t", "N"},
        {usm_design_outputs, USM_DESIGN_POWER_IN, "power_in", "W"},
        {usm_design_outputs, USM_DESIGN_POWER_OUT, "power_out", "W"},
        {usm_design_outputs, USM_DESIGN_POWER_DAMPING, "power_damping", "W"},
        {usm_design_outputs, USM_DESIGN_POWER_SLIP, "power_slip", "W"},
    };
    const int n = (int)(sizeof want / sizeof want[0]);
    CHECK(n == USM_OUT_COUNT + USM_STEADY_COUNT + USM_SEED_COUNT + USM_POWER_COUNT +
                   USM_DESIGN_COUNT, "%d outputs listed", n);
    for (int i = 0; i < n; ++i) {
        const usm_output_info *o = &want[i].table[want[i].index];
        CHECK(strcmp(o->name, want[i].name) == 0 && strcmp(o->unit, want[i].unit) == 0,
              "output %s: table says %s [%s], expected [%s]", want[i].name, o->name, o->unit,
              want[i].unit);
    }
    /* the meaning at the index: R* and Z along a motion and on the stationary solution */
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        usm_params p;
        usm_params_default(&p);
        double x[USM_MAX_NX] = {0}, xd[USM_MAX_NX] = {0}, out[USM_OUT_COUNT];
        double u[USM_MAX_NU] = {0}, y[USM_STEADY_COUNT];
        const double th = 0.0123;
        for (int i = 0; i < m->nx; ++i)
            x[i] = 0.1 * (i + 1), xd[i] = 0.01 * (i + 2);
        if (m->coordinates == 1) { /* the tilt vector: a^2 + b^2 = sin(theta)^2 */
            x[m->x_a] = 0.6 * sin(th);
            x[m->x_b] = -0.8 * sin(th);
        } else
            x[m->x_theta] = th;
        m->outputs(x, xd, 0.0, &p, out);
        const double Rs = p.R * cos(th) - p.H * sin(th), Z = p.R * sin(th) + p.H * cos(th);
        CHECK(fabs(out[USM_OUT_R_STAR] - Rs) <= 1e-15 && fabs(out[USM_OUT_Z] - Z) <= 1e-15,
              "%s: outputs R_star %.17g (%.17g), Z %.17g (%.17g)", m->name, out[USM_OUT_R_STAR],
              Rs, out[USM_OUT_Z], Z);
        u[m->u_theta] = th;
        u[m->u_alpha] = 0.3;
        if (m->u_phidot_R >= 0)
            u[m->u_phidot_R] = -200.0;
        m->steady_outputs(u, &p, y);
        CHECK(fabs(y[USM_STEADY_R_STAR] - Rs) <= 1e-15 && fabs(y[USM_STEADY_Z] - Z) <= 1e-15,
              "%s: steady_outputs R_star %.17g, Z %.17g", m->name, y[USM_STEADY_R_STAR],
              y[USM_STEADY_Z]);
    }
}

/* Every output of the kernels that take parameters, as bytes. */
static void kernel_bits(const usm_model *m, const usm_params *p, unsigned char *buf, size_t *len)
{
    double x[USM_MAX_NX], v[USM_MAX_NX], u[USM_MAX_NU] = {0};
    double out[USM_MAX_NX * USM_MAX_NX * 3 + USM_MAX_NU * USM_NPARAMS + 64];
    for (int i = 0; i < m->nx; ++i)
        x[i] = 0.05 * (i + 1), v[i] = 0.7 - 0.1 * i;
    u[m->u_theta] = 0.02;
    u[m->u_alpha] = 0.4;
    if (m->u_phidot_R >= 0)
        u[m->u_phidot_R] = -150.0;
    *len = 0;
#define TAKE(nvals)                                                                                \
    do {                                                                                           \
        memcpy(buf + *len, out, sizeof(double) * (size_t)(nvals));                                 \
        *len += sizeof(double) * (size_t)(nvals);                                                  \
    } while (0)
    const int n = m->nx, nu = m->nu;
    m->mass(x, p, out);
    TAKE(n * n);
    m->rhs(x, 0.3e-5, p, out);
    TAKE(n);
    m->jac_rhs(x, 0.3e-5, p, out);
    TAKE(n * n);
    m->jac_mass(x, v, p, out);
    TAKE(n * n);
    m->linearisation(x, v, 0.3e-5, p, out);
    TAKE(3 * n * n);
    m->steady_residual(u, p, out);
    TAKE(nu);
    m->steady_jacobian(u, p, out);
    TAKE(nu * nu);
    m->steady_outputs(u, p, out);
    TAKE(USM_STEADY_COUNT);
    m->steady_seed(0.02, p, out);
    TAKE(USM_SEED_COUNT);
    m->steady_power(u, p, out);
    TAKE(USM_POWER_COUNT);
    m->steady_state(u, 0.1, 0.2e-5, p, out);
    TAKE(n);
#undef TAKE
}

static void check_couplings(void)
{
    static unsigned char a[1 << 16], b[1 << 16];
    for (int k = 0; k < USM_NMODELS; ++k) {
        const usm_model *m = usm_models[k];
        const int axisymmetric = strstr(m->assumptions, "stator_inertia=axisymmetric") != NULL;
        for (int j = 0; j < USM_NPARAMS; ++j) {
            const usm_param_coupling *c = usm_param_coupled(m, j);
            if (axisymmetric && j == USM_P_I_yy)
                CHECK(c && c->param == USM_P_I_yy && c->equals == USM_P_I_xx,
                      "%s: I_yy not tied to I_xx", m->name);
            else
                CHECK(c == NULL, "%s: %s tied to %s", m->name, usm_param_table[j].name,
                      c ? usm_param_table[c->equals].name : "");
        }
        CHECK(usm_param_coupled(m, -1) == NULL && usm_param_coupled(m, USM_NPARAMS) == NULL,
              "%s: coupled out of range", m->name);
        if (!axisymmetric)
            continue;
        usm_params p, q;
        size_t la, lb;
        usm_params_default(&p);
        /* the kernels do not read I_yy ... */
        kernel_bits(m, &p, a, &la);
        q = p;
        q.I_yy = 3.7 * p.I_yy;
        kernel_bits(m, &q, b, &lb);
        CHECK(la == lb && memcmp(a, b, la) == 0, "%s: a kernel reads I_yy", m->name);
        /* ... but do read I_xx */
        q = p;
        q.I_xx = 1.3 * p.I_xx;
        kernel_bits(m, &q, b, &lb);
        CHECK(la == lb && memcmp(a, b, la) != 0, "%s: no kernel reads I_xx", m->name);
        /* applying the coupling */
        char msg[USM_MSG_LEN];
        CHECK(usm_params_check(&q, m, msg) != USM_OK && strstr(msg, "I_yy") &&
                  strstr(msg, "I_xx") && strstr(msg, "axisymmetric stator"),
              "%s: I_yy != I_xx accepted or unnamed: %s", m->name, msg);
        usm_params r = q;
        usm_params_couple(m, &r, USM_P_F0); /* F0 ties nothing */
        CHECK(memcmp(&r, &q, sizeof r) == 0, "%s: coupling from F0 changed a parameter", m->name);
        usm_params_couple(m, &r, USM_P_I_xx);
        CHECK(r.I_yy == q.I_xx && r.I_xx == q.I_xx, "%s: I_yy %g after coupling, I_xx %g",
              m->name, r.I_yy, r.I_xx);
        r.I_yy = q.I_yy;
        r.I_zz = 2.5e-8;
        usm_params_couple(m, &r, -1);
        CHECK(r.I_yy == q.I_xx && r.I_zz == 2.5e-8, "%s: couple(-1)", m->name);
        CHECK(usm_params_check(&r, m, msg) == USM_OK, "%s: coupled point refused: %s", m->name,
              msg);
    }
}

/* The ranges (docs/cli.md, "Ranges"): every default inside its range; a value
 * typed in the wrong unit refused by the setter and the check with the range
 * and the unit it was meant in (the reproducers: f = 38 solved at 38 Hz,
 * phase_error = 35 taken as 35 rad); a scatter in the wrong unit or of a
 * parameter the model does not read refused by usm_tolerance_vary_check. */
static void check_ranges(void)
{
    char msg[USM_MSG_LEN];
    usm_params p;
    usm_params_default(&p);
    for (int k = 0; k < USM_NPARAMS; ++k) {
        const double v = usm_param_defaults[k];
        CHECK(usm_param_ranges[k].lo <= v && v <= usm_param_ranges[k].hi,
              "%s: default %g outside its range", usm_param_table[k].name, v);
        CHECK(usm_param_check_value(k, v, msg) == USM_OK, "%s: default refused: %s",
              usm_param_table[k].name, msg);
    }
    CHECK(usm_params_set(&p, "f", 38.0, msg) == USM_EINPUT && p.f == 37000.0,
          "f = 38 Hz accepted by usm_params_set");
    CHECK(strcmp(msg, "f = 38 Hz is outside 1 kHz..1 MHz; did you mean 38 kHz?") == 0,
          "f = 38: \"%s\"", msg);
    CHECK(usm_params_set(&p, "f", 38000.0, msg) == USM_OK, "f = 38 kHz refused: %s", msg);
    usm_params_default(&p);
    p.phase_error = 35.0;
    CHECK(usm_params_check(&p, usm_model_variant("3dof", "imperfect"), msg) == USM_EINPUT &&
              strstr(msg, "phase_error = 35 rad is outside") && strstr(msg, "did you mean 35 deg?"),
          "phase_error = 35: \"%s\"", msg);
    p.phase_error = 35.0 * 3.14159265358979 / 180.0;
    CHECK(usm_params_check(&p, usm_model_variant("3dof", "imperfect"), msg) == USM_OK,
          "phase_error = 35 deg refused: %s", msg);
    CHECK(usm_param_check_value(USM_P_F0, 400.0, msg) == USM_EINPUT &&
              strstr(msg, "did you mean 400 mN?"), "F0 = 400: \"%s\"", msg);
    CHECK(usm_param_check_value(USM_P_T, 1e-310, msg) == USM_EINPUT && strstr(msg, "underflow"),
          "T = 1e-310 (subnormal): \"%s\"", msg);

    usm_tolerance_vary v;
    usm_params_default(&p);
    const usm_model *ideal = usm_model_find("3dof");
    const usm_model *imperfect = usm_model_variant("3dof", "imperfect");
    CHECK(usm_tolerance_vary_parse("F0=normal:5", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, ideal, &p, msg) == USM_EINPUT &&
              strstr(msg, "F0: the standard deviation 5 N exceeds the value 0.4 N"),
          "F0=normal:5 (sigma 5 N on 0.4 N): \"%s\"", msg);
    CHECK(usm_tolerance_vary_parse("F0=normal:5%", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, ideal, &p, msg) == USM_OK, "F0=normal:5%%: %s", msg);
    CHECK(usm_tolerance_vary_parse("f=uniform:37.5:38.5", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, ideal, &p, msg) == USM_EINPUT &&
              strstr(msg, "did you mean 38.5 kHz?"), "f=uniform:37.5:38.5: \"%s\"", msg);
    CHECK(usm_tolerance_vary_parse("amp_imbalance=normal:0.01", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, ideal, &p, msg) == USM_EINPUT &&
              strstr(msg, "ideal motor"), "amp_imbalance on an ideal model: \"%s\"", msg);
    CHECK(usm_tolerance_vary_check(&v, imperfect, &p, msg) == USM_OK,
          "amp_imbalance on the imperfect model: %s", msg);
    CHECK(usm_tolerance_vary_parse("phase_error=normal:5", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, imperfect, &p, msg) == USM_EINPUT &&
              strstr(msg, "did you mean 5 deg?"), "phase_error=normal:5 (5 rad): \"%s\"", msg);
    char long_msg[1024];
    CHECK(usm_tolerance_vary_parse_units("--vary", "phase_error=normal:5deg", &v, long_msg) ==
                  USM_OK &&
              usm_tolerance_vary_check(&v, imperfect, &p, msg) == USM_OK,
          "phase_error=normal:5deg refused: %s / %s", long_msg, msg);
    CHECK(usm_tolerance_vary_parse("I_yy=normal:1%", &v, msg) == USM_OK &&
              usm_tolerance_vary_check(&v, ideal, &p, msg) == USM_EINPUT && strstr(msg, "I_xx"),
          "I_yy, tied to I_xx: \"%s\"", msg);
}

/* |a - b| within tol of the larger magnitude of the two (and of floor). */
static int near(double a, double b, double tol, double floor)
{
    return fabs(a - b) <= tol * fmax(fmax(fabs(a), fabs(b)), floor);
}

/* The orbit's M and A = df/dx - d(M v)/dx at v = xbar' at time t. */
static void orbit_MA(const usm_model *m, const double *u, double beta, double t,
                     const usm_params *p, double *M, double *A)
{
    const int n = m->nx;
    double orbit[2 * USM_MAX_NX], Jm[USM_MAX_NX * USM_MAX_NX];
    m->steady_state(u, beta, t, p, orbit);
    const double *x = orbit + m->steady_state_out.x, *xd = orbit + m->steady_state_out.xdot;
    m->mass(x, p, M);
    m->jac_rhs(x, t, p, A);
    m->jac_mass(x, xd, p, Jm);
    for (int i = 0; i < n * n; ++i)
        A[i] -= Jm[i];
}

static void check_model_offsets(const usm_model *m)
{
    const int n = m->nx, nu = m->nu, nn = n * n;
    usm_params p;
    usm_params_default(&p);
    double x[USM_MAX_NX], v[USM_MAX_NX], u[USM_MAX_NU] = {0};
    for (int i = 0; i < n; ++i)
        x[i] = 0.05 * (i + 1), v[i] = 0.7 - 0.1 * i;
    if (m->coordinates == 1) {
        x[m->x_a] = 0.006;
        x[m->x_b] = -0.008;
    } else
        x[m->x_theta] = 0.01;
    u[m->u_theta] = 0.0123;
    u[m->u_alpha] = 0.4;
    if (m->u_phidot_R >= 0)
        u[m->u_phidot_R] = -150.0;
    const double t = 0.3e-5;
    /* linearisation: [M, df/dx, d(Mv)/dx] against the separate kernels */
    double lin[3 * USM_MAX_NX * USM_MAX_NX], M[USM_MAX_NX * USM_MAX_NX];
    double Jf[USM_MAX_NX * USM_MAX_NX], Jm[USM_MAX_NX * USM_MAX_NX];
    m->linearisation(x, v, t, &p, lin);
    m->mass(x, &p, M);
    m->jac_rhs(x, t, &p, Jf);
    m->jac_mass(x, v, &p, Jm);
    int bad = 0;
    for (int i = 0; i < nn; ++i)
        bad += !near(lin[m->linearisation_out.mass + i], M[i], 1e-12, 1e-300) ||
               !near(lin[m->linearisation_out.jac_rhs + i], Jf[i], 1e-12, 1e-300) ||
               !near(lin[m->linearisation_out.jac_mass + i], Jm[i], 1e-12, 1e-300);
    CHECK(bad == 0, "%s: linearisation's blocks differ from mass, jac_rhs, jac_mass in %d entries",
          m->name, bad);
    /* steady_state: the rate block is the derivative of the state block in t */
    double y[USM_STEADY_COUNT];
    m->steady_outputs(u, &p, y);
    const double beta = y[USM_STEADY_BETA], h = 1e-4 / p.f;
    double o0[2 * USM_MAX_NX], op[2 * USM_MAX_NX], om[2 * USM_MAX_NX];
    m->steady_state(u, beta, t, &p, o0);
    m->steady_state(u, beta, t + h, &p, op);
    m->steady_state(u, beta, t - h, &p, om);
    for (int i = 0; i < n; ++i) {
        const int a = m->steady_state_out.x + i;
        const double fd = (op[a] - om[a]) / (2 * h);
        CHECK(near(o0[m->steady_state_out.xdot + i], fd, 1e-6, 1e-3),
              "%s: steady_state rate %d: %.10g, differences %.10g", m->name, i,
              o0[m->steady_state_out.xdot + i], fd);
    }
    /* floquet_direction along dt = 1: the derivatives of M and A in t */
    if (m->floquet_direction) {
        double d[2 * USM_MAX_NX * USM_MAX_NX], du[USM_MAX_NU] = {0};
        double Mp[USM_MAX_NX * USM_MAX_NX], Mm[USM_MAX_NX * USM_MAX_NX];
        double Ap[USM_MAX_NX * USM_MAX_NX], Am[USM_MAX_NX * USM_MAX_NX];
        usm_params dp;
        memset(&dp, 0, sizeof dp);
        m->floquet_direction(u, t, du, 1.0, &p, &dp, d);
        orbit_MA(m, u, beta, t + h, &p, Mp, Ap);
        orbit_MA(m, u, beta, t - h, &p, Mm, Am);
        double scaleM = 1e-300, scaleA = 1e-300;
        for (int i = 0; i < nn; ++i) {
            scaleM = fmax(scaleM, fabs(Mp[i] - Mm[i]) / (2 * h));
            scaleA = fmax(scaleA, fabs(Ap[i] - Am[i]) / (2 * h));
        }
        /* the differences' rounding, where the linearisation is constant in t */
        for (int i = 0; i < nn; ++i) {
            scaleM = fmax(scaleM, 1e-9 * fabs(Mp[i]) / h);
            scaleA = fmax(scaleA, 1e-9 * fabs(Ap[i]) / h);
        }
        bad = 0;
        for (int i = 0; i < nn; ++i)
            bad += fabs(d[m->floquet_direction_out.dM + i] - (Mp[i] - Mm[i]) / (2 * h)) >
                       1e-5 * scaleM ||
                   fabs(d[m->floquet_direction_out.dA + i] - (Ap[i] - Am[i]) / (2 * h)) >
                       1e-5 * scaleA;
        CHECK(bad == 0, "%s: floquet_direction's dM, dA along t differ from differences in %d "
              "entries", m->name, bad);
    }
    /* steady_design_jacobian: [dy/du, dy/dp], y the design quantities */
    double D[USM_DESIGN_COUNT * (USM_MAX_NU + USM_NPARAMS)];
    m->steady_design_jacobian(u, &p, D);
    for (int j = 0; j <= nu; ++j) { /* the unknowns, then the load T */
        double yp[USM_DESIGN_COUNT], ym[USM_DESIGN_COUNT];
        for (int side = 0; side < 2; ++side) {
            double us[USM_MAX_NU], so[USM_STEADY_COUNT], pw[USM_POWER_COUNT];
            usm_params q = p;
            memcpy(us, u, sizeof us);
            const double step = j < nu ? 1e-6 * fmax(1.0, fabs(u[j])) : 1e-6 * fabs(p.T);
            if (j < nu)
                us[j] += side ? -step : step;
            else
                q.T += side ? -step : step;
            m->steady_outputs(us, &q, so);
            m->steady_power(us, &q, pw);
            double *yy = side ? ym : yp;
            yy[USM_DESIGN_ROTOR_SPEED] = so[USM_STEADY_ROTOR_SPEED];
            yy[USM_DESIGN_F_N] = so[USM_STEADY_F_N];
            yy[USM_DESIGN_F_T] = so[USM_STEADY_F_T];
            yy[USM_DESIGN_POWER_IN] = pw[USM_POWER_POWER_IN];
            yy[USM_DESIGN_POWER_OUT] = pw[USM_POWER_POWER_OUT];
            yy[USM_DESIGN_POWER_DAMPING] = pw[USM_POWER_POWER_DAMPING];
            yy[USM_DESIGN_POWER_SLIP] = pw[USM_POWER_POWER_SLIP];
        }
        const double step = j < nu ? 1e-6 * fmax(1.0, fabs(u[j])) : 1e-6 * fabs(p.T);
        for (int r = 0; r < USM_DESIGN_COUNT; ++r) {
            const double fd = (yp[r] - ym[r]) / (2 * step);
            const double got = j < nu ? D[m->steady_design_jacobian_out.du + r * nu + j]
                                      : D[m->steady_design_jacobian_out.dp + r * USM_NPARAMS + USM_P_T];
            CHECK(near(got, fd, 1e-5, 1e-6 * (fabs(yp[r]) + 1e-12) / step),
                  "%s: steady_design_jacobian row %s, %s: %.10g, differences %.10g", m->name,
                  usm_design_outputs[r].name, j < nu ? m->unknown_names[j] : "T", got, fd);
        }
    }
    /* friction: the slope is the derivative of mu */
    if (m->friction) {
        double f0[USM_FRICTION_COUNT], fp[USM_FRICTION_COUNT], fm[USM_FRICTION_COUNT];
        const double vr = 0.013, dv = 1e-7;
        m->friction(vr, &p, f0);
        m->friction(vr + dv, &p, fp);
        m->friction(vr - dv, &p, fm);
        CHECK(near(f0[USM_FRICTION_SLOPE], (fp[USM_FRICTION_MU] - fm[USM_FRICTION_MU]) / (2 * dv),
                   1e-6, 1e-9),
              "%s: friction slope %.10g, differences of mu %.10g", m->name,
              f0[USM_FRICTION_SLOPE], (fp[USM_FRICTION_MU] - fm[USM_FRICTION_MU]) / (2 * dv));
    }
}

/* The unilateral kernels' blocks against their definitions. */
static void check_unilateral_offsets(const usm_model *m)
{
    const usm_unilateral *U = m->unilateral;
    const int n = m->nx, ny = U->ny;
    usm_params p;
    usm_params_default(&p);
    p.e_impact = 0.4;
    double x[USM_MAX_NX], xd[USM_MAX_NX], o[USM_OUT_COUNT];
    for (int i = 0; i < n; ++i)
        x[i] = 0.05 * (i + 1), xd[i] = 0.3 - 0.07 * i;
    x[m->x_theta] = 0.01;
    const double t = 0.3e-5;
    /* guard_closed: F_n of outputs, its gradients by differences */
    double gc[1 + 2 * USM_MAX_NX], gp[1 + 2 * USM_MAX_NX], gm[1 + 2 * USM_MAX_NX];
    U->guard_closed(x, xd, t, &p, gc);
    m->outputs(x, xd, t, &p, o);
    CHECK(near(gc[U->guard_closed_out.F_n], o[USM_OUT_F_N], 1e-12, 1e-9),
          "%s: guard_closed F_n %.10g, outputs %.10g", m->name, gc[U->guard_closed_out.F_n],
          o[USM_OUT_F_N]);
    for (int j = 0; j < 2 * n; ++j) {
        double xs[USM_MAX_NX], xds[USM_MAX_NX];
        double *w = j < n ? xs : xds;
        const int k = j < n ? j : j - n;
        memcpy(xs, x, sizeof xs);
        memcpy(xds, xd, sizeof xds);
        const double step = 1e-6 * fmax(1.0, fabs(w[k]));
        w[k] += step;
        U->guard_closed(xs, xds, t, &p, gp);
        w[k] -= 2 * step;
        U->guard_closed(xs, xds, t, &p, gm);
        const double fd = (gp[U->guard_closed_out.F_n] - gm[U->guard_closed_out.F_n]) / (2 * step);
        const double got = j < n ? gc[U->guard_closed_out.dF_n_dx + k]
                                 : gc[U->guard_closed_out.dF_n_dxdot + k];
        CHECK(near(got, fd, 1e-5, 1e-6 * fabs(gc[U->guard_closed_out.F_n]) / step),
              "%s: guard_closed gradient %d: %.10g, differences %.10g", m->name, j, got, fd);
    }
    /* separation: y = (x, Z, Z'[, w_R]), dy/dx with the identity on x */
    double sj[USM_MAX_NY * (USM_MAX_NY + 1)], yv[USM_MAX_NY];
    U->separation(x, &p, sj);
    memcpy(yv, sj + U->separation_out.y, sizeof(double) * (size_t)ny);
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        bad += yv[i] != x[i];
        for (int j = 0; j < n; ++j)
            bad += sj[U->separation_out.dy_dx + i * n + j] != (i == j);
    }
    CHECK(bad == 0, "%s: separation's y or dy/dx is not (x, identity) in %d entries", m->name, bad);
    /* guard_open: gap = Z_R - Z(theta), 0 at the separation; dgap/dZ_R = 1 */
    double gg[1 + USM_MAX_NY];
    U->guard_open(yv, &p, gg);
    CHECK(fabs(gg[U->guard_open_out.gap]) <= 1e-15 && gg[U->guard_open_out.dgap_dy + U->y_Z_R] == 1,
          "%s: guard_open at the separation: gap %.3g, dgap/dZ_R %.17g", m->name,
          gg[U->guard_open_out.gap], gg[U->guard_open_out.dgap_dy + U->y_Z_R]);
    yv[U->y_Z_R] += 1e-6;
    U->guard_open(yv, &p, gg);
    CHECK(near(gg[U->guard_open_out.gap], 1e-6, 1e-9, 1e-6), "%s: gap %.17g after Z_R + 1e-6",
          m->name, gg[U->guard_open_out.gap]);
    /* the impacts: Newton's law gap'+ = -e gap'- (and, sticking, v_rel+ = 0);
       the rotor approaching at 1 mm/s */
    yv[U->y_Z_R] -= 1e-6;
    double cv[2 + 2 * USM_MAX_NY], cva[2 + 2 * USM_MAX_NY], imp[USM_MAX_NY + 2];
    U->contact_velocity(yv, &p, cv);
    yv[U->y_Z_Rdot] += -1e-3 - cv[U->contact_velocity_out.gap_rate];
    U->contact_velocity(yv, &p, cv);
    CHECK(near(cv[U->contact_velocity_out.gap_rate], -1e-3, 1e-9, 1e-3) &&
              cv[U->contact_velocity_out.dgap_rate_dy + U->y_Z_Rdot] == 1,
          "%s: contact_velocity gap' %.17g (-1e-3), dgap'/dZ_Rdot %.17g", m->name,
          cv[U->contact_velocity_out.gap_rate],
          cv[U->contact_velocity_out.dgap_rate_dy + U->y_Z_Rdot]);
    U->impact_stick(yv, &p, imp);
    U->contact_velocity(imp + U->impact_out.y, &p, cva);
    CHECK(near(cva[U->contact_velocity_out.gap_rate], 0.4e-3, 1e-9, 1e-3) &&
              fabs(cva[U->contact_velocity_out.v_rel]) <= 1e-12 * fmax(1.0, fabs(cv[U->contact_velocity_out.v_rel])) &&
              imp[U->impact_out.P_n] > 0,
          "%s: sticking impact: gap'+ %.10g (0.4e-3), v_rel+ %.3g, P_n %.3g", m->name,
          cva[U->contact_velocity_out.gap_rate], cva[U->contact_velocity_out.v_rel],
          imp[U->impact_out.P_n]);
    if (m->slip) {
        U->impact_slide(yv, 1.0, &p, imp);
        U->contact_velocity(imp + U->impact_out.y, &p, cva);
        CHECK(near(cva[U->contact_velocity_out.gap_rate], 0.4e-3, 1e-9, 1e-3) &&
                  near(imp[U->impact_out.P_t], p.mu0 * imp[U->impact_out.P_n], 1e-12, 1e-30),
              "%s: sliding impact: gap'+ %.10g (0.4e-3), P_t %.6g, mu0 P_n %.6g", m->name,
              cva[U->contact_velocity_out.gap_rate], imp[U->impact_out.P_t],
              p.mu0 * imp[U->impact_out.P_n]);
    }
}

static void check_offsets(void)
{
    for (int k = 0; k < USM_NMODELS; ++k) {
        check_model_offsets(usm_models[k]);
        if (usm_models[k]->unilateral)
            check_unilateral_offsets(usm_models[k]);
    }
    /* the headers name the descriptors' offsets */
    CHECK(usm_model_3dof.linearisation_out.jac_rhs == USM_3DOF_LINEARISATION_OUT_JAC_RHS &&
              usm_model_3dof.linearisation_out.jac_mass == USM_3DOF_LINEARISATION_OUT_JAC_MASS &&
              usm_model_3dof.steady_state_out.xdot == USM_3DOF_STEADY_STATE_OUT_XDOT &&
              usm_model_3dof.floquet_direction_out.dA == USM_3DOF_FLOQUET_DIRECTION_OUT_DA &&
              usm_model_3dof.steady_design_jacobian_out.dp == USM_3DOF_STEADY_DESIGN_JACOBIAN_OUT_DP,
          "usm_3dof.h's offsets differ from usm_model_3dof's");
    const usm_unilateral *U = usm_model_4dof_imperfect_unilateral.unilateral;
    CHECK(U->guard_closed_out.dF_n_dxdot == USM_4DOF_IMPERFECT_UNILATERAL_GUARD_CLOSED_OUT_DF_N_DXDOT &&
              U->separation_out.dy_dx == USM_4DOF_IMPERFECT_UNILATERAL_SEPARATION_OUT_DY_DX &&
              U->impact_out.P_t == USM_4DOF_IMPERFECT_UNILATERAL_IMPACT_SLIDE_OUT_P_T &&
              U->contact_velocity_out.dv_rel_dy ==
                  USM_4DOF_IMPERFECT_UNILATERAL_CONTACT_VELOCITY_OUT_DV_REL_DY,
          "usm_4dof_imperfect_unilateral.h's offsets differ from its descriptor's");
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: test_params_contracts docs/cli.md\n");
        return 2;
    }
    check_params();
    check_documented(argv[1]);
    for (int k = 0; k < USM_NMODELS; ++k)
        check_columns(usm_models[k]);
    check_outputs();
    check_couplings();
    check_ranges();
    check_offsets();
    printf("%s: %d failures\n", argv[0], failures);
    return failures != 0;
}
