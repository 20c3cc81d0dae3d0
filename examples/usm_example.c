/* usm_example: a program that uses an installed usm library.
 *
 * It finds the stationary solution of the 3-DOF stick model with the paper's
 * parameters and its Floquet multipliers (the runtime), then evaluates the
 * generated kernels directly at the stationary state at t = 0: the mass matrix
 * M(x), the right-hand side f(x, t), its Jacobian df/dx, and the residual
 * M(x) x' - f(x, t) of the equations of motion on the stationary orbit, where
 * the angles turn at constant rates: x' = (phidot, thetadot, psidot, 0, 0, 0)
 * (zero up to rounding: a torque of order 1e-12 N m against m0 = 5e-3 N m).
 * Prints one JSON object, every number with 17 significant digits.
 *
 * Build it (see examples/CMakeLists.txt and examples/Makefile):
 *   cmake -S examples -B build-example -DCMAKE_PREFIX_PATH=PREFIX && cmake --build build-example
 *   cc usm_example.c $(pkg-config --cflags --libs usm) -o usm_example
 */
#include <math.h>
#include <stdio.h>

#include <gsl/gsl_errno.h>
#include <usm/usm.h>
#include <usm/usm_3dof.h>

#define NX USM_3DOF_NX

static void print_vector(const char *name, const double *v, int n)
{
    printf("  \"%s\": [", name);
    for (int i = 0; i < n; ++i)
        printf("%s%.17g", i ? ", " : "", v[i]);
    printf("],\n");
}

static void print_matrix(const char *name, const double *a, int n)
{
    printf("  \"%s\": [\n", name);
    for (int i = 0; i < n; ++i) {
        printf("    [");
        for (int j = 0; j < n; ++j)
            printf("%s%.17g", j ? ", " : "", a[i * n + j]);
        printf("]%s\n", i + 1 < n ? "," : "");
    }
    printf("  ],\n");
}

int main(void)
{
    /* The library reports numerical failures as status codes; GSL's default
     * handler would abort instead (see usm.h). */
    gsl_set_error_handler_off();

    const usm_model *model = usm_model_find("3dof");
    if (!model) {
        fprintf(stderr, "usm_example: no 3dof model in this library\n");
        return 1;
    }
    usm_params p;
    usm_params_default(&p);

    /* Runtime: the stationary solution (the primary root: the smallest tilt). */
    usm_steady *steady = usm_steady_alloc(model);
    if (!steady)
        return 1;
    int status = usm_steady_solve(steady, &p, NULL);
    if (status != USM_OK) {
        fprintf(stderr, "usm_example: %s\n", usm_steady_message(steady));
        usm_steady_free(steady);
        return status;
    }
    const usm_steady_solution *sol = usm_steady_root(steady, 0);

    /* Runtime: its Floquet multipliers over [0, T], the default method. */
    usm_floquet *floquet = usm_floquet_alloc(model);
    usm_floquet_result fl;
    if (!floquet) {
        usm_steady_free(steady);
        return 1;
    }
    status = usm_floquet_compute(floquet, &p, sol, 0.0, NULL, &fl);
    if (status != USM_OK) {
        fprintf(stderr, "usm_example: %s\n", usm_floquet_message(floquet));
        usm_floquet_free(floquet);
        usm_steady_free(steady);
        return status;
    }

    /* Kernels, called directly: the state on the stationary orbit at t = 0
     * and its rate, M(x), f(x, 0), df/dx.  Every array has the length the
     * generated header gives for the kernel that writes it
     * (USM_3DOF_<KERNEL>_OUT_LEN): steady_state writes the state and its
     * rate, 2 NX numbers. */
    const double t = 0.0;
    double orbit[USM_3DOF_STEADY_STATE_OUT_LEN], mass[USM_3DOF_MASS_OUT_LEN],
        rhs[USM_3DOF_RHS_OUT_LEN], jac[USM_3DOF_JAC_RHS_OUT_LEN], xdot[NX], residual[NX];
    usm_3dof_steady_state(sol->u, sol->beta, t, &p, orbit);
    const double *x = orbit; /* orbit = [x (NX), dx/dt (NX)] */
    usm_3dof_mass(x, &p, mass);
    usm_3dof_rhs(x, t, &p, rhs);
    usm_3dof_jac_rhs(x, t, &p, jac);
    /* the angles turn at constant rates: x' = (phidot, thetadot, psidot, 0, 0, 0) */
    xdot[USM_3DOF_X_PHI] = x[USM_3DOF_X_PHIDOT];
    xdot[USM_3DOF_X_THETA] = x[USM_3DOF_X_THETADOT];
    xdot[USM_3DOF_X_PSI] = x[USM_3DOF_X_PSIDOT];
    xdot[USM_3DOF_X_PHIDOT] = xdot[USM_3DOF_X_THETADOT] = xdot[USM_3DOF_X_PSIDOT] = 0.0;
    double residual_max = 0.0;
    for (int i = 0; i < NX; ++i) {
        residual[i] = -rhs[i];
        for (int j = 0; j < NX; ++j)
            residual[i] += mass[i * NX + j] * xdot[j];
        residual_max = fmax(residual_max, fabs(residual[i]));
    }

    printf("{\n");
    printf("  \"usm_version\": \"%s\",\n", usm_version());
    printf("  \"generator_version\": \"%s\",\n", usm_generator_version());
    printf("  \"model\": \"%s\",\n", model->name);
    printf("  \"theta\": %.17g,\n", sol->theta);
    printf("  \"alpha\": %.17g,\n", sol->alpha);
    printf("  \"beta\": %.17g,\n", sol->beta);
    printf("  \"rotor_speed\": %.17g,\n", sol->rotor_speed);
    print_vector("state_t0", x, NX);
    print_matrix("mass", mass, NX);
    print_vector("rhs", rhs, NX);
    print_matrix("jac_rhs", jac, NX);
    print_vector("orbit_residual", residual, NX);
    printf("  \"orbit_residual_max\": %.17g,\n", residual_max);
    printf("  \"m0\": %.17g,\n", p.m0);
    printf("  \"multipliers\": [\n");
    for (int i = 0; i < fl.n; ++i)
        printf("    [%.17g, %.17g]%s\n", fl.re[i], fl.im[i], i + 1 < fl.n ? "," : "");
    printf("  ],\n");
    printf("  \"max_modulus\": %.17g,\n", fl.max_modulus);
    printf("  \"stable\": %s\n", fl.stable ? "true" : "false");
    printf("}\n");

    usm_floquet_free(floquet);
    usm_steady_free(steady);
    return fflush(stdout) == 0 ? 0 : 1;
}
