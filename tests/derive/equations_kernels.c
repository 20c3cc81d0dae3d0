/* The compiled kernels of one generated model at given points, for
 * tests/derive/equations_proof.py (the document's equations against the C).
 * usage: equations_kernels MODEL < points
 *        equations_kernels MODEL --sizes
 * --sizes prints the model's lengths: nx, nu, USM_NPARAMS, USM_STEADY_COUNT
 * (the input and output lines below are made of them).
 * Each input line: x (nx values), t, the parameters (usm_param_table order),
 * u (nu values).  Each output line: M (nx*nx, row-major), f (nx), the
 * stationary residuals (nu), the stationary outputs (USM_STEADY_COUNT) and
 * the state on the stationary orbit at t (nx, beta from those outputs). */
#include <stdio.h>
#include <string.h>

#include "usm_kernels.h"

static int read_values(double *v, int n)
{
    for (int i = 0; i < n; ++i)
        if (scanf("%lf", &v[i]) != 1)
            return 0;
    return 1;
}

static void print_values(const double *v, int n)
{
    for (int i = 0; i < n; ++i)
        printf("%s%.17g", i ? " " : "", v[i]);
}

int main(int argc, char **argv)
{
    const usm_model *m = NULL;
    if (argc != 2 && !(argc == 3 && strcmp(argv[2], "--sizes") == 0)) {
        fprintf(stderr, "usage: equations_kernels MODEL [--sizes] < points\n");
        return 2;
    }
    for (int k = 0; k < USM_NMODELS; ++k)
        if (strcmp(usm_models[k]->name, argv[1]) == 0)
            m = usm_models[k];
    if (!m) {
        fprintf(stderr, "equations_kernels: no model %s\n", argv[1]);
        return 2;
    }
    if (argc == 3) {
        printf("%d %d %d %d\n", m->nx, m->nu, USM_NPARAMS, (int)USM_STEADY_COUNT);
        return 0;
    }
    for (;;) {
        double x[USM_MAX_NX], u[USM_MAX_NU], t, pv[USM_NPARAMS];
        double mass[USM_MAX_NX * USM_MAX_NX], f[USM_MAX_NX], r[USM_MAX_NU];
        double s[USM_STEADY_COUNT], xbar[2 * USM_MAX_NX]; /* steady_state: x and x' */
        usm_params p;
        if (!read_values(x, m->nx))
            break;
        if (!read_values(&t, 1) || !read_values(pv, USM_NPARAMS) || !read_values(u, m->nu)) {
            fprintf(stderr, "equations_kernels: incomplete input line\n");
            return 2;
        }
        for (int k = 0; k < USM_NPARAMS; ++k)
            memcpy((char *)&p + usm_param_table[k].offset, &pv[k], sizeof(double));
        m->mass(x, &p, mass);
        m->rhs(x, t, &p, f);
        m->steady_residual(u, &p, r);
        m->steady_outputs(u, &p, s);
        m->steady_state(u, s[USM_STEADY_BETA], t, &p, xbar);
        print_values(mass, m->nx * m->nx);
        printf(" | ");
        print_values(f, m->nx);
        printf(" | ");
        print_values(r, m->nu);
        printf(" | ");
        print_values(s, USM_STEADY_COUNT);
        printf(" | ");
        print_values(xbar, m->nx);
        printf("\n");
    }
    return 0;
}
