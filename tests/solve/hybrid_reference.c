/* hybrid_reference: the Jacobian of the event-driven period map of a model
 * whose contact may open, by central differences in extended precision (the
 * reference of test_hybrid_unilateral's saltation multipliers; docs/unilateral.md).
 *
 * Why a program of its own, in long double: central differences of a period
 * map in double carry its rounding divided by the step.  After the
 * monodromy's amplification that rounding is about 1e-10 of the state, so a
 * double-precision reference scatters by about 1e-6 in the multipliers
 * (measured 0.9e-6..8.7e-6 over steps of 1e-4..2e-5 of each scale), the very
 * tolerance it is to judge.  The x87 format's 64-bit significand rounds 2^11
 * times finer.  The model's kernels are generated/'s own C, compiled here
 * with every double a long double and <tgmath.h>'s sin, cos, atan, sqrt
 * choosing the long double functions; a constant in them rounded to double
 * (e.g. 1.0/3.0) changes the model by 1e-16, smoothly, and adds no noise.
 * This program links nothing else (so the long double usm_params of this
 * unit never meets libusm's), and test_hybrid_unilateral runs it.
 *
 * The map: the closed mode M(x) x' = f(x, t) until F_n = 0, the open mode
 * M(y) y' = f(y, t) until the gap is 0, the library's resets (solve/impact.h:
 * separation; no impact where the rotor does not approach or touches slower
 * than v_land while the closed mode would pull it off; else the impact,
 * sticking, or sliding where sticking needs |P_t| > mu0 P_n; landing unless
 * the rotor leaves faster than v_land, and only where F_n >= 0).
 * Fixed steps (classical Runge-Kutta, N a period: the map is a smooth
 * function of the start, no step selection); a guard's sign change inside a
 * step is located by the Illinois method on the step's length from the
 * step's start.  State: the spin u = phidot + psidot in place of phidot (in
 * x, rounding phidot and psidot, each of size Omega, puts noise of size
 * eps Omega into a rate whose scale is Omega theta).
 *
 * Usage (every number a C floating constant; test_hybrid_unilateral writes %a):
 *   hybrid_reference MODEL N H t0 T v_land p_1 .. p_23 x_1 .. x_nx s_1 .. s_nx
 * MODEL 3dof_imperfect_unilateral or 4dof_imperfect_unilateral, N steps a
 * period, H the difference step relative to the scales s, x the start in
 * the model's coordinates.  Prints "switches K", "end e_1 .. e_nx" and "fd"
 * followed by nx rows of the Jacobian d w(T) / d w(0) in the spin
 * coordinates w, sixth-order central differences with steps H s_j.
 * Exit 1 with a message on bad input, 2 where the map fails (a mode left
 * open at the period's end, or the switches change with the start).
 */
#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the generated declarations in extended precision (the kernels are
 * compiled so: tests/CMakeLists.txt, long_double.h) */
#include "long_double.h"
#include "usm_3dof_imperfect_unilateral.h"
#include "usm_4dof_imperfect_unilateral.h"
#undef double

typedef long double real;
/* the x87 format's 64-bit significand (2^11 finer than double's): where long
 * double is double this program would be no reference */
_Static_assert(LDBL_MANT_DIG >= 64, "long double must be wider than double");

enum { NMAX = USM_MAX_NY };

typedef struct {
    const char *name;
    int nx, ny, slip, x_phidot, x_psidot, x_theta;
    void (*mass)(const real *x, const usm_params *p, real *out);
    void (*rhs)(const real *x, real t, const usm_params *p, real *out);
    void (*outputs)(const real *x, const real *xd, real t, const usm_params *p, real *out);
    void (*open_mass)(const real *y, const usm_params *p, real *out);
    void (*open_rhs)(const real *y, real t, const usm_params *p, real *out);
    void (*guard_open)(const real *y, const usm_params *p, real *out);
    void (*contact_velocity)(const real *y, const usm_params *p, real *out);
    void (*separation)(const real *x, const usm_params *p, real *out);
    void (*impact_stick)(const real *y, const usm_params *p, real *out);
    void (*impact_slide)(const real *y, real s, const usm_params *p, real *out);
} kernels;

#define KERNELS(M, U, SLIP)                                                                  \
    {#M "_imperfect_unilateral", U##_NX, U##_OPEN_MASS_Y_LEN, SLIP, U##_X_PHIDOT, U##_X_PSIDOT, \
     U##_X_THETA, usm_##M##_imperfect_unilateral_mass, usm_##M##_imperfect_unilateral_rhs,      \
     usm_##M##_imperfect_unilateral_outputs, usm_##M##_imperfect_unilateral_open_mass,          \
     usm_##M##_imperfect_unilateral_open_rhs, usm_##M##_imperfect_unilateral_guard_open,        \
     usm_##M##_imperfect_unilateral_contact_velocity, usm_##M##_imperfect_unilateral_separation, \
     usm_##M##_imperfect_unilateral_impact_stick, usm_##M##_imperfect_unilateral_impact_slide}

static const kernels models[] = {
    KERNELS(3dof, USM_3DOF_IMPERFECT_UNILATERAL, 0),
    KERNELS(4dof, USM_4DOF_IMPERFECT_UNILATERAL, 1),
};

typedef struct {
    const kernels *k;
    usm_params p;
    real v_land;
    int mode;   /* 0 closed (state length nx), 1 open (ny) */
    int failed; /* a singular mass matrix was met */
} map_t;

/* A x = b, Gaussian elimination with partial pivoting; A is destroyed */
static int solve(int n, real *A, real *b)
{
    for (int c = 0; c < n; ++c) {
        int piv = c;
        for (int r = c + 1; r < n; ++r)
            if (fabsl(A[r * n + c]) > fabsl(A[piv * n + c]))
                piv = r;
        if (A[piv * n + c] == 0)
            return -1;
        if (piv != c) {
            for (int j = 0; j < n; ++j) {
                const real s = A[c * n + j];
                A[c * n + j] = A[piv * n + j];
                A[piv * n + j] = s;
            }
            const real s = b[c];
            b[c] = b[piv];
            b[piv] = s;
        }
        for (int r = c + 1; r < n; ++r) {
            const real l = A[r * n + c] / A[c * n + c];
            for (int j = c; j < n; ++j)
                A[r * n + j] -= l * A[c * n + j];
            b[r] -= l * b[c];
        }
    }
    for (int r = n - 1; r >= 0; --r) {
        real s = b[r];
        for (int j = r + 1; j < n; ++j)
            s -= A[r * n + j] * b[j];
        b[r] = s / A[r * n + r];
    }
    return 0;
}

/* the model's coordinates from the spin coordinates */
static void to_x(const map_t *F, const real *w, real *x)
{
    memcpy(x, w, sizeof(real) * (size_t)(F->mode ? F->k->ny : F->k->nx));
    x[F->k->x_phidot] = w[F->k->x_phidot] - w[F->k->x_psidot];
}

/* rates in the spin coordinates, in mode F->mode; -1 (and F->failed) where
 * the mass matrix is singular */
static int rates(map_t *F, real t, const real *w, real *dw)
{
    real A[NMAX * NMAX], x[NMAX];
    const int n = F->mode ? F->k->ny : F->k->nx;
    to_x(F, w, x);
    if (F->mode) {
        F->k->open_mass(x, &F->p, A);
        F->k->open_rhs(x, t, &F->p, dw);
    } else {
        F->k->mass(x, &F->p, A);
        F->k->rhs(x, t, &F->p, dw);
    }
    if (solve(n, A, dw) != 0) {
        F->failed = 1;
        return -1;
    }
    dw[F->k->x_phidot] += dw[F->k->x_psidot];
    return 0;
}

static real normal_force(map_t *F, real t, const real *w)
{
    real x[NMAX], xd[NMAX], o[USM_OUT_COUNT];
    const int mode = F->mode;
    F->mode = 0;
    const int rc = rates(F, t, w, xd);
    F->mode = mode;
    if (rc != 0)
        return NAN;
    xd[F->k->x_phidot] -= xd[F->k->x_psidot];
    to_x(F, w, x);
    F->k->outputs(x, xd, t, &F->p, o);
    return o[USM_OUT_F_N];
}

static real guard(map_t *F, real t, const real *w)
{
    if (F->mode == 0)
        return normal_force(F, t, w);
    real x[NMAX], g[1 + NMAX];
    to_x(F, w, x);
    F->k->guard_open(x, &F->p, g);
    return g[0];
}

/* one classical Runge-Kutta step of length h from (t, w) */
static void step(map_t *F, real t, const real *w, real h, real *out)
{
    real k[4][NMAX], z[NMAX];
    const int n = F->mode ? F->k->ny : F->k->nx;
    static const real c[4] = {0, 0.5L, 0.5L, 1};
    for (int s = 0; s < 4; ++s) {
        for (int i = 0; i < n; ++i)
            z[i] = w[i] + (s ? c[s] * h * k[s - 1][i] : 0);
        if (rates(F, t + c[s] * h, z, k[s]) != 0)
            memset(k[s], 0, sizeof k[s]); /* F->failed: the map fails */
    }
    for (int i = 0; i < n; ++i)
        out[i] = w[i] + h * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]) / 6;
}

/* the reset at a guard (the library's rules, solve/impact.h, at e_impact as
 * given): 1 a switch, 0 a touch without impact (no reset) */
static int reset(map_t *F, real t, real *w)
{
    const kernels *K = F->k;
    const int ip = K->x_phidot, is = K->x_psidot, ny = K->ny;
    real x[NMAX], out[NMAX + 2], cv[2 + 2 * NMAX], sj[NMAX * (NMAX + 1)];
    to_x(F, w, x);
    if (F->mode == 0) {
        K->separation(x, &F->p, sj);
        memcpy(w, sj, sizeof(real) * (size_t)ny);
        F->mode = 1;
    } else {
        /* no impact where the rotor does not approach, or touches slower
         * than v_land while the closed mode would pull it off */
        K->contact_velocity(x, &F->p, cv);
        const real v = -cv[0];
        if (!(v > 0) || (v <= F->v_land && normal_force(F, t, w) < 0))
            return 0;
        K->impact_stick(x, &F->p, out);
        if (K->slip && fabsl(out[ny + 1]) > F->p.mu0 * out[ny])
            K->impact_slide(x, out[ny + 1] > 0 ? 1.0L : -1.0L, &F->p, out);
        memcpy(w, out, sizeof(real) * (size_t)ny);
        K->contact_velocity(w, &F->p, cv);
        w[ip] += w[is];
        if (!(cv[0] > F->v_land) && normal_force(F, t, w) >= 0)
            F->mode = 0;
        return 1;
    }
    w[ip] += w[is];
    return 1;
}

/* w0 -> w1 over [t0, t0 + T] in N steps; the number of switches in *nsw */
static int period_map(map_t *F, real t0, real T, int N, const real *w0, real *w1, int *nsw)
{
    real w[NMAX], we[NMAX];
    real t = t0;
    F->mode = 0;
    F->failed = 0;
    *nsw = 0;
    memcpy(w, w0, sizeof(real) * (size_t)F->k->nx);
    for (int k = 0; k < N; ++k) {
        const real tn = t0 + T * (k + 1) / N;
        while (t < tn) {
            const real g0 = guard(F, t, w);
            step(F, t, w, tn - t, we);
            const real g1 = guard(F, tn, we);
            if (!(g0 > 0 && g1 <= 0)) {
                memcpy(w, we, sizeof we);
                t = tn;
                continue;
            }
            real a = 0, b = tn - t, ga = g0, gb = g1, tau = b;
            int side = 0;
            for (int it = 0; it < 400 && b - a > 4e-19L * (tn - t); ++it) {
                tau = (a * gb - b * ga) / (gb - ga);
                step(F, t, w, tau, we);
                const real gt = guard(F, t + tau, we);
                if (gt > 0) {
                    a = tau;
                    ga = gt;
                    if (side == 1)
                        gb /= 2;
                    side = 1;
                } else {
                    b = tau;
                    gb = gt;
                    if (side == -1)
                        ga /= 2;
                    side = -1;
                }
            }
            step(F, t, w, tau, we);
            memcpy(w, we, sizeof we);
            t += tau;
            if (reset(F, t, w) && ++*nsw > 64)
                return -1;
        }
    }
    if (F->mode != 0 || F->failed)
        return -1;
    memcpy(w1, w, sizeof(real) * (size_t)F->k->nx);
    return 0;
}

static real number(const char *s, const char *what)
{
    char *end;
    errno = 0;
    const real v = strtold(s, &end);
    if (end == s || *end || errno || !isfinite(v)) {
        fprintf(stderr, "hybrid_reference: %s: '%s' is not a finite number\n", what, s);
        exit(1);
    }
    return v;
}

int main(int argc, char **argv)
{
    const kernels *K = NULL;
    for (size_t i = 0; argc > 1 && i < sizeof models / sizeof models[0]; ++i)
        if (!strcmp(argv[1], models[i].name))
            K = &models[i];
    if (!K) {
        fprintf(stderr, "hybrid_reference: MODEL: '%s' is not 3dof_imperfect_unilateral or "
                "4dof_imperfect_unilateral\n", argc > 1 ? argv[1] : "");
        return 1;
    }
    const int nx = K->nx;
    if (argc != 7 + USM_NPARAMS + 2 * nx) {
        fprintf(stderr, "hybrid_reference: %d arguments, %d wanted (MODEL N H t0 T v_land, %d "
                "parameters, %d states, %d scales)\n", argc - 1, 6 + USM_NPARAMS + 2 * nx,
                USM_NPARAMS, nx, nx);
        return 1;
    }
    const real Nr = number(argv[2], "N");
    if (!(Nr >= 4 && Nr <= 1e7 && Nr == floorl(Nr))) {
        fprintf(stderr, "hybrid_reference: N: %s is not a whole number in 4..1e7\n", argv[2]);
        return 1;
    }
    const int N = (int)Nr;
    const real H = number(argv[3], "H"), t0 = number(argv[4], "t0");
    const real T = number(argv[5], "T");
    map_t F;
    memset(&F, 0, sizeof F);
    F.k = K;
    F.v_land = number(argv[6], "v_land");
    if (!(H > 0 && T > 0)) {
        fprintf(stderr, "hybrid_reference: H and T must be positive\n");
        return 1;
    }
    real *pv = (real *)&F.p; /* usm_params: USM_NPARAMS reals, in the table's order */
    _Static_assert(sizeof(usm_params) == USM_NPARAMS * sizeof(real), "usm_params: reals only");
    for (int i = 0; i < USM_NPARAMS; ++i)
        pv[i] = number(argv[7 + i], "parameter");
    real w0[NMAX], sc[NMAX], w1[NMAX];
    for (int i = 0; i < nx; ++i) {
        w0[i] = number(argv[7 + USM_NPARAMS + i], "state");
        sc[i] = number(argv[7 + USM_NPARAMS + nx + i], "scale");
    }
    w0[K->x_phidot] += w0[K->x_psidot];
    int nsw0 = 0;
    if (period_map(&F, t0, T, N, w0, w1, &nsw0) != 0) {
        fprintf(stderr, "hybrid_reference: the period map ends open or switches too often\n");
        return 2;
    }
    printf("switches %d\nend", nsw0);
    w1[K->x_phidot] -= w1[K->x_psidot];
    for (int i = 0; i < nx; ++i)
        printf(" %.21Lg", w1[i]);
    printf("\nfd\n");
    static const real off[6] = {-3, -2, -1, 1, 2, 3};
    static const real c6[6] = {-1, 9, -45, 45, -9, 1};
    real J[NMAX][NMAX];
    for (int j = 0; j < nx; ++j) {
        real f[6][NMAX], wp[NMAX];
        const real h = H * sc[j];
        for (int e = 0; e < 6; ++e) {
            int nsw = 0;
            memcpy(wp, w0, sizeof wp);
            wp[j] += off[e] * h;
            if (period_map(&F, t0, T, N, wp, f[e], &nsw) != 0 || nsw != nsw0) {
                fprintf(stderr, "hybrid_reference: the map's switches change along state %d "
                        "(%d against %d)\n", j, nsw, nsw0);
                return 2;
            }
        }
        for (int i = 0; i < nx; ++i) {
            real d = 0;
            for (int e = 0; e < 6; ++e)
                d += c6[e] * f[e][i];
            J[i][j] = d / (60 * h);
        }
    }
    for (int i = 0; i < nx; ++i) {
        for (int j = 0; j < nx; ++j)
            printf("%s%.21Lg", j ? " " : "", J[i][j]);
        printf("\n");
    }
    return ferror(stdout) || fflush(stdout) ? 2 : 0;
}
