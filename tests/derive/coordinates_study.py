#!/usr/bin/python3
"""How many digits the Floquet multipliers lose to the z-x-z Euler
angles, measured against a tilt-vector formulation of the same motor.

A measurement script, not a ctest: it prints a table.  Run from the tree's
root with the pinned Python (Debian's /usr/bin/python3, python3-sympy,
python3-mpmath) after a build:

    /usr/bin/python3 tests/derive/coordinates_study.py build [model]

or, Euler angles only at the six points of the issue (a minute):

    /usr/bin/python3 tests/derive/coordinates_study.py build --points [models]

and the reference of the test multipliers_reference:

    /usr/bin/python3 tests/derive/coordinates_study.py build --reference tests/solve/multipliers_reference.h

and the paper's twist law (3dof, 4dof) at the six points, by Taylor steps of
the variational equation in extended precision (a few minutes a model):

    /usr/bin/python3 tests/derive/coordinates_study.py build --paper [models]

model is 3dof_twist_integrated (default); the twist_integrated models have a
linearisation that is constant in frame A, so that their multipliers are
exp(T eig(A)) and their 50-digit reference needs no ODE solver; under the
paper's twist law it is affine in t (paper_points).  The reference file
holds both (write_reference).  derive/ itself now derives the tilt-vector
coordinates (assumption coordinates, variant tilt); the hand-written sympy
derivation below (tilt_model) stays as a second, independent one.

What it does, at the paper's parameters:
1. Euler angles (derive/'s model, as the C kernels use it): the stationary
   solution to 50 digits (mpmath), the linearisation A = M^-1 (df/dx -
   d(Mv)/dx) on the orbit and its multipliers exp(T eig A), evaluated (a) in
   50 digits, (b) by the compiled C kernels of libusm (double), the
   eigenvalues of (b) then taken in 50 digits, so that the difference is the
   double-precision linearisation alone.
2. Tilt-vector coordinates (a, b, chi): e_z2 in the housing frame rotated
   back by Omega t, a + i b = exp(-i Omega t) (e_z2,X + i e_z2,Y), and
   chi = phi + psi, derived here from the same physics (Euler's equations in
   the housing frame, the same torques (2.8)-(2.11), the same contact law)
   without Euler angles; rows projected on the co-rotating frame, so that the
   stationary orbit is a fixed point and A is constant again.  Same (a), (b)
   (here (b) is the same expressions evaluated in double by Python).
3. The condition number of the mass matrix and the 2-norm of the monodromy
   matrix in both sets (Euler also in the runtime's tangent-map coordinates).
"""
import ctypes
import json
import os
import subprocess
import sys

import mpmath as mp
import sympy as sp

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "derive"))
from variants import generated_models                      # noqa: E402
from usm_derive.model import derive_model, P, t, PARAMETERS, OMEGA   # noqa: E402
from usm_derive.kinematics import rot_z                    # noqa: E402

mp.mp.dps = 50


def run_usm(build, model, variant, sets=()):
    extra = [a for kv in sets for a in ("--set", kv)]
    out = subprocess.run([os.path.join(build, "usm"), "steady", "--model", model,
                          "--variant", variant, "--json"] + extra, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def mpmat(rows):
    return mp.matrix([[mp.mpf(v) for v in r] for r in rows])


def tilt_model(contact):
    """The stick model with the integrated twist law in co-rotating tilt-vector
    coordinates (a, b, chi) and the extra state tau; returns (states, mass,
    rhs, v) like derive/'s Model."""
    if contact != "stick":
        raise NotImplementedError("slip contact")
    Om = OMEGA
    a_f, b_f, chi_f = (sp.Function(n, real=True)(t) for n in ("a", "b", "chi"))
    tau = sp.Symbol("tau", real=True)
    ct, st = sp.cos(Om * t), sp.sin(Om * t)
    nx = a_f * ct - b_f * st
    ny = a_f * st + b_f * ct
    s2 = a_f ** 2 + b_f ** 2
    c = sp.sqrt(1 - s2)
    s = sp.sqrt(s2)
    n = sp.Matrix([nx, ny, c])                     # e_z2 in the housing frame N
    k = sp.Matrix([-ny, nx, 0])                    # e_Z x e_z2 = sin(theta) e_x1
    K = sp.Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R_tilt = sp.eye(3) + K + K * K / (1 + c)       # e_Z -> e_z2 about e_x1
    W = R_tilt.diff(t) * R_tilt.T
    omega = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]]) + chi_f.diff(t) * n
    I_N = R_tilt * sp.diag(P["I_xx"], P["I_xx"], P["I_zz"]) * R_tilt.T   # axisymmetric
    L = I_N * omega
    e_x1 = k / s
    e_y1 = sp.Matrix([0, 0, 1]).cross(e_x1)
    e_y2 = n.cross(e_x1)
    r_c = P["R"] * e_y2 + P["H"] * n               # highest point of the stator
    Z = r_c[2]
    R_star = r_c.dot(e_y1)
    v_c = omega.cross(r_c).dot(e_x1)
    F_n = P["M"] * Z.diff(t, 2) + P["F0"] + P["c_R"] * (Z - P["H"]) + P["d_R"] * Z.diff(t)
    w_R = v_c / R_star                             # stick (2.4)
    F_t = (P["I_R"] * w_R.diff(t) + P["T"]) / R_star   # rotor (2.2)
    theta = sp.asin(s)
    M_E = sp.Matrix([P["m0"] * ct, P["m0"] * st, 0])
    M_R = P["c_r"] * theta / s * k + sp.Matrix([0, 0, P["c_t"] * tau])
    M_D = sp.diag(P["d_r"], P["d_r"], P["d_t"]) * omega
    M_C = r_c.cross(-F_t * e_x1 - F_n * sp.Matrix([0, 0, 1]))
    rows = rot_z(-Om * t) * (L.diff(t) - (M_E - M_R - M_D + M_C))
    coords = [a_f, b_f, chi_f]
    names = ["a", "b", "chi"]
    q = [sp.Symbol(nm, real=True) for nm in names]
    qd = [sp.Symbol(nm + "dot", real=True) for nm in names]
    qdd = [sp.Symbol(nm + "ddot", real=True) for nm in names]
    subs = ([(cf.diff(t, 2), qdd[i]) for i, cf in enumerate(coords)]
            + [(cf.diff(t), qd[i]) for i, cf in enumerate(coords)]
            + [(cf, q[i]) for i, cf in enumerate(coords)])
    rows = rows.subs(subs)
    M_q = rows.jacobian(qdd)
    f_q = -rows.subs({x: 0 for x in qdd})
    states = q + qd + [tau]
    mass = sp.zeros(7, 7)
    for i in range(3):
        mass[i, i] = 1
    mass[3:6, 3:6] = M_q
    mass[6, 6] = 1
    rhs = sp.Matrix(qd + list(f_q) + [omega[2].subs(subs)])
    v = [sp.Symbol(f"v{i}", real=True) for i in range(7)]
    return states, mass, rhs, v


def linearisation_fns(states, mass, rhs, v):
    """(50-digit functions, double functions) of mass, rhs, df/dx, d(Mv)/dx."""
    jr = rhs.jacobian(states)
    jm = (mass * sp.Matrix(v)).jacobian(states)
    pars = [P[nm] for nm, *_ in PARAMETERS]
    args = [states, v, t, pars]
    exprs = (mass, rhs, jr, jm)
    return ([sp.lambdify(args, e, modules="mpmath", cse=True) for e in exprs],
            [sp.lambdify(args, e, modules=[{"ImmutableDenseMatrix": list}, "math"], cse=True)
             for e in exprs])


def A_of(fns, x, xd, tt, pv, conv):
    mass_f, rhs_f, jr_f, jm_f = fns
    M = mpmat(conv(mass_f(x, xd, tt, pv)))
    J = mpmat(conv(jr_f(x, xd, tt, pv))) - mpmat(conv(jm_f(x, xd, tt, pv)))
    res = mpmat(conv(rhs_f(x, xd, tt, pv))) - M * mp.matrix([[e] for e in xd])
    return M, mp.inverse(M) * J, res


def tolist(m):
    m = sp.Matrix(m) if not isinstance(m, list) else m
    if isinstance(m, list):
        return [r if isinstance(r, list) else [r] for r in m]
    return [[m[i, j] for j in range(m.shape[1])] for i in range(m.shape[0])]


def conv_mp(m):
    return tolist(m)


def conv_double(m):
    return [[float(e) for e in r] for r in tolist(m)]


def multipliers(A, period):
    ev = mp.eig(A, left=False, right=False)
    mu = sorted((mp.exp(e * period) for e in ev), key=lambda z: (-abs(z), mp.arg(z)))
    return mu


def match_err(mu, ref):
    """max over ref of min |mu_i - ref_j| (both sorted lists of the same length)."""
    left = list(mu)
    worst = mp.mpf(0)
    for r in ref:
        j = min(range(len(left)), key=lambda i: abs(left[i] - r))
        worst = max(worst, abs(left[j] - r))
        left.pop(j)
    return worst


def pipeline53(G, period, ref):
    """The double pipeline emulated in 53-bit arithmetic: the monodromy
    exp(T G) of a constant linearisation, then its eigenvalues; the digits of
    the worst multiplier against the 50-digit reference."""
    with mp.workprec(53):
        Gs = mp.matrix(G.rows, G.cols)
        for i in range(G.rows):
            for j in range(G.cols):
                Gs[i, j] = +G[i, j]
        Phi = mp.expm(Gs * period)
        ev = mp.eig(Phi, left=False, right=False)
    err = match_err(list(ev), ref)
    return float(-mp.log10(err)) if err > 0 else 50.0


def svd_cond(M):
    sv = mp.svd_r(M, compute_uv=False)
    sv = [abs(x) for x in sv]
    return max(sv) / min(sv)


def norm2(M):
    sv = mp.svd_r(M, compute_uv=False)
    return max(abs(x) for x in sv)


# The six points: the paper's; T, f, m0 varied.
POINTS = [(), ("T=0",), ("T=1.2e-4",), ("f=36000",), ("f=38500",), ("m0=0.008",)]


def euler_points(build, name, refs=None):
    """Euler angles only (fast): at each point, the digits of usm's
    multipliers and of the C kernels' G (eigenvalues in 50 digits); with
    refs a list, (point, 50-digit multipliers) appended to it."""
    spec = {g[0]: g for g in generated_models()}[name]
    _, base, variant, assumptions, _ = spec
    m = derive_model(name, assumptions)
    pnames = [nm for nm, *_ in PARAMETERS]
    psyms = [P[nm] for nm in pnames]
    n = len(m.states)
    r_f = sp.lambdify([m.unknowns, psyms], m.residual, modules="mpmath")
    beta_f = sp.lambdify([m.unknowns, psyms], m.steady_outputs["beta"], modules="mpmath")
    beta_sym = [x for x in m.steady_state.free_symbols if x.name == "beta"][0]
    xs_f = sp.lambdify([m.unknowns, beta_sym, t, psyms],
                       list(m.steady_state) + list(m.steady_rate), modules="mpmath")
    fe_mp, _ = linearisation_fns(m.states, m.mass, m.rhs, m.v)
    lib = ctypes.CDLL(os.path.join(build, "libusm.so"))
    for sets in POINTS:
        js = run_usm(build, base, variant, sets)
        pdouble = [float(js["parameters"][nm]) for nm in pnames]
        pmp = [mp.mpf(x) for x in pdouble]
        period = 1 / pmp[pnames.index("f")]
        guess = [mp.mpf(js["theta"]), mp.mpf(js["alpha"])]
        if len(m.unknowns) == 3:
            guess.append(mp.mpf(js["rotor_speed"]))
        u = mp.findroot(lambda *uu: [e for e in r_f(list(uu), pmp)], guess)
        u = [u[i] for i in range(len(m.unknowns))]
        orb = xs_f(u, beta_f(u, pmp), 0, pmp)
        x_mp, xd_mp = orb[:n], orb[n:]
        _, A_e, _ = A_of(fe_mp, x_mp, xd_mp, 0, pmp, conv_mp)
        mu_ref = multipliers(A_e, period)
        if refs is not None:
            refs.append((sets, mu_ref))
        x_d, xd_d = [float(e) for e in x_mp], [float(e) for e in xd_mp]
        Dn = ctypes.c_double * (n * n)
        xc, vc = (ctypes.c_double * n)(*x_d), (ctypes.c_double * n)(*xd_d)
        pc = (ctypes.c_double * len(pdouble))(*pdouble)
        out_m, out_r, out_m2 = Dn(), Dn(), Dn()
        getattr(lib, f"usm_{name}_mass")(xc, pc, out_m)
        getattr(lib, f"usm_{name}_jac_rhs")(xc, ctypes.c_double(0), pc, out_r)
        getattr(lib, f"usm_{name}_jac_mass")(xc, vc, pc, out_m2)
        Mc, Jc = mp.matrix(n, n), mp.matrix(n, n)
        for i in range(n):
            for j in range(n):
                Mc[i, j] = out_m[n * i + j]
                Jc[i, j] = out_r[n * i + j] - out_m2[n * i + j]
        mu_c = multipliers(mp.inverse(Mc) * Jc, period)
        mu_usm = [mp.mpc(a, b) for a, b in js["floquet"]["multipliers"]]

        def digits(err):
            return float(-mp.log10(err)) if err > 0 else 50.0
        print(f"{name} {' '.join(sets) or 'paper':10s} theta {float(u[0]):.3e}  usm "
              f"{digits(match_err(mu_usm, mu_ref)):5.2f}  C-kernel G "
              f"{digits(match_err(mu_c, mu_ref)):5.2f}  |mu|max {float(abs(mu_ref[1])):.4f}")


def balance_mp(G):
    """D with D^-1 G D balanced (Parlett-Reinsch, powers of 2): the 1-norms of
    row and column i made comparable."""
    n = G.rows
    d = [mp.mpf(1)] * n
    B = G.copy()
    for _ in range(100):
        done = True
        for i in range(n):
            c = sum(abs(B[j, i]) for j in range(n) if j != i)
            r = sum(abs(B[i, j]) for j in range(n) if j != i)
            if c == 0 or r == 0:
                continue
            f = mp.mpf(1)
            while c < r / 2:
                c, r, f = c * 2, r / 2, f * 2
            while c > r * 2:
                c, r, f = c / 2, r * 2, f / 2
            if f != 1:
                done = False
                d[i] *= f
                for j in range(n):
                    B[i, j] /= f
                    B[j, i] *= f
        if done:
            break
    return d, B


def taylor_monodromy(G0, G1, period, steps):
    """Phi(T) of Phi' = (G0 + t G1) Phi, Phi(0) = I, by the Taylor series of
    each of `steps` equal steps, summed until the terms are below the working
    precision: (k + 1) c_{k+1} = G(t_n) c_k + G1 c_{k-1}."""
    n = G0.rows
    h = period / steps
    tol = mp.mpf(10) ** (-mp.mp.dps - 3)
    Phi = mp.eye(n)
    for k in range(steps):
        Gn = G0 + (k * h) * G1
        c_prev, c = mp.zeros(n, n), mp.eye(n)
        P = mp.eye(n)
        hk = mp.mpf(1)
        for j in range(1, 400):
            c_prev, c = c, (Gn * c + G1 * c_prev) / j
            hk *= h
            term = c * hk
            P += term
            if mp.mnorm(term, 1) < tol and j > 4:
                break
        Phi = P * Phi
    return Phi


def paper_points(build, name, refs, steps=None, dps=34):
    """The paper's twist law (3dof, 4dof): the linearisation about the orbit
    depends on t, affinely in frame A (checked at T/2).  The monodromy from
    t0 = 0 by Taylor steps in 34-digit arithmetic, in the balanced tangent-map
    coordinates, at N and 2N steps (their difference is printed: the
    convergence check); the multipliers are its eigenvalues."""
    spec = {g[0]: g for g in generated_models()}[name]
    _, base, variant, assumptions, _ = spec
    m = derive_model(name, assumptions)
    pnames = [nm for nm, *_ in PARAMETERS]
    psyms = [P[nm] for nm in pnames]
    n = len(m.states)
    r_f = sp.lambdify([m.unknowns, psyms], m.residual, modules="mpmath")
    beta_f = sp.lambdify([m.unknowns, psyms], m.steady_outputs["beta"], modules="mpmath")
    beta_sym = [x for x in m.steady_state.free_symbols if x.name == "beta"][0]
    xs_f = sp.lambdify([m.unknowns, beta_sym, t, psyms],
                       list(m.steady_state) + list(m.steady_rate), modules="mpmath")
    tm_f = sp.lambdify([m.states, psyms], m.tangent_map, modules="mpmath")
    fe_mp, _ = linearisation_fns(m.states, m.mass, m.rhs, m.v)
    with mp.workdps(dps):
        for sets in POINTS:
            js = run_usm(build, base, variant, sets)
            pdouble = [float(js["parameters"][nm]) for nm in pnames]
            pmp = [mp.mpf(x) for x in pdouble]
            period = 1 / pmp[pnames.index("f")]
            guess = [mp.mpf(js["theta"]), mp.mpf(js["alpha"])]
            if len(m.unknowns) == 3:
                guess.append(mp.mpf(js["rotor_speed"]))
            u = mp.findroot(lambda *uu: [e for e in r_f(list(uu), pmp)], guess)
            u = [u[i] for i in range(len(m.unknowns))]
            beta = beta_f(u, pmp)

            def G_at(tt):
                orb = xs_f(u, beta, tt, pmp)
                _, G, _ = A_of(fe_mp, orb[:n], orb[n:], tt, pmp, conv_mp)
                return G, orb[:n]
            G0, x0 = G_at(mp.mpf(0))
            GT, _ = G_at(period)
            Gh, _ = G_at(period / 2)
            affine = mp.mnorm(Gh - (G0 + GT) / 2, 1) / mp.mnorm(G0, 1)
            S = mpmat(tolist(tm_f(x0, pmp)))
            Sinv = mp.inverse(S)
            dsc, _ = balance_mp(S * G0 * Sinv)
            Dm = mp.diag(dsc)
            Sb = mp.inverse(Dm) * S
            Sbi = mp.inverse(Sb)
            B0 = Sb * G0 * Sbi
            B1 = Sb * ((GT - G0) / period) * Sbi
            N = steps or max(64, int(mp.mnorm(B0 * period, 1)) * 2)
            Phi1 = taylor_monodromy(B0, B1, period, N)
            Phi2 = taylor_monodromy(B0, B1, period, 2 * N)
            mu1 = sorted(mp.eig(Phi1, left=False, right=False), key=lambda z: (-abs(z), mp.arg(z)))
            mu2 = sorted(mp.eig(Phi2, left=False, right=False), key=lambda z: (-abs(z), mp.arg(z)))
            conv = match_err(mu1, mu2)
            mu_usm = [mp.mpc(a, b) for a, b in js["floquet"]["multipliers"]]
            err = match_err(mu_usm, mu2) if len(mu_usm) == len(mu2) else mp.mpf(1)
            print(f"{name} {' '.join(sets) or 'paper':10s} theta {float(u[0]):.3e}  affine "
                  f"{mp.nstr(affine, 2)}  |B0 T|_1 {mp.nstr(mp.mnorm(B0 * period, 1), 3)}  "
                  f"N {N}: |mu(N) - mu(2N)| {mp.nstr(conv, 2)}  usm error {mp.nstr(err, 3)} "
                  f"({float(-mp.log10(err)) if err > 0 else 50:.2f} digits)", flush=True)
            if refs is not None:
                refs.append((sets, mu2))


def write_reference(build, path):
    """tests/solve/multipliers_reference.h: the 50-digit multipliers (to 20
    significant digits) of both twist_integrated models at the six points."""
    out = ["/* Generated by tests/derive/coordinates_study.py BUILD --reference PATH:",
           " * the Floquet multipliers (from t0 = 0) at six points, from derive/'s",
           " * equations in mpmath.  twist_integrated models: exp(T eig G), the stationary",
           " * solution, the linearisation and its eigenvalues in 50-digit arithmetic.",
           " * 3dof, 4dof (the paper's twist law, G affine in t): the monodromy by Taylor",
           " * steps in 30-digit arithmetic in the balanced tangent-map coordinates, 32",
           " * and 64 steps agreeing to 1e-25 or better (printed when written).",
           " * Do not edit. */",
           "typedef struct {", "    const char *model;", "    double f, T, m0;",
           "    int n;", "    double re[9], im[9];", "} multipliers_reference;", "",
           "static const multipliers_reference MULTIPLIERS_REFERENCE[] = {"]
    for name in ("3dof_twist_integrated", "4dof_twist_integrated", "3dof", "4dof"):
        refs = []
        if name in ("3dof", "4dof"):
            paper_points(build, name, refs, steps=32, dps=30)
        else:
            euler_points(build, name, refs)
        for sets, mu in refs:
            kv = dict(x.split("=") for x in sets)
            re = ", ".join(mp.nstr(mp.re(z), 20, min_fixed=-1, max_fixed=1) if abs(mp.re(z)) > 1e-30
                           else "0.0" for z in mu)
            im = ", ".join(mp.nstr(mp.im(z), 20, min_fixed=-1, max_fixed=1) if abs(mp.im(z)) > 1e-30
                           else "0.0" for z in mu)
            out.append(f'    {{"{name}", {kv.get("f", "37000")}, {kv.get("T", "6.46e-5")}, '
                       f'{kv.get("m0", "0.005")}, {len(mu)},')
            out.append(f"     {{{re}}},")
            out.append(f"     {{{im}}}}},")
    out.append("};")
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")


def main():
    if len(sys.argv) > 3 and sys.argv[2] == "--reference":
        write_reference(sys.argv[1], sys.argv[3])
        return
    if len(sys.argv) > 2 and sys.argv[2] == "--paper":
        for name in sys.argv[3:] or ["3dof", "4dof"]:
            paper_points(sys.argv[1], name, None)
        return
    if len(sys.argv) > 2 and sys.argv[2] == "--points":
        for name in sys.argv[3:] or ["3dof_twist_integrated", "4dof_twist_integrated"]:
            euler_points(sys.argv[1], name)
        return
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    name = sys.argv[2] if len(sys.argv) > 2 else "3dof_twist_integrated"
    spec = {g[0]: g for g in generated_models()}[name]
    _, base, variant, assumptions, _ = spec
    m = derive_model(name, assumptions)
    js = run_usm(build, base, variant)
    pnames = [nm for nm, *_ in PARAMETERS]
    pdouble = [float(js["parameters"][nm]) for nm in pnames]
    pmp = [mp.mpf(x) for x in pdouble]
    period = 1 / pmp[pnames.index("f")]

    # 1. stationary solution to 50 digits
    r_f = sp.lambdify([m.unknowns, [P[nm] for nm in pnames]], m.residual, modules="mpmath")
    u0 = [mp.mpf(js["theta"]), mp.mpf(js["alpha"])]
    u = mp.findroot(lambda th, al: [e for e in r_f([th, al], pmp)], u0)
    u = [u[0], u[1]]
    beta_f = sp.lambdify([m.unknowns, [P[nm] for nm in pnames]],
                         m.steady_outputs["beta"], modules="mpmath")
    beta = beta_f(u, pmp)
    beta_sym = [s for s in m.steady_state.free_symbols if s.name == "beta"][0]
    xs_f = sp.lambdify([m.unknowns, beta_sym, t, [P[nm] for nm in pnames]],
                       list(m.steady_state) + list(m.steady_rate), modules="mpmath")
    orb = xs_f(u, beta, 0, pmp)
    x_mp, xd_mp = orb[:7], orb[7:]
    x_d, xd_d = [float(e) for e in x_mp], [float(e) for e in xd_mp]
    print(f"{name}: theta = {mp.nstr(u[0], 20)}, alpha = {mp.nstr(u[1], 20)}")
    print(f"  usm's theta rel. error {mp.nstr(abs(mp.mpf(js['theta']) / u[0] - 1), 3)}")

    fe_mp, fe_d = linearisation_fns(m.states, m.mass, m.rhs, m.v)
    M_e, A_e, res_e = A_of(fe_mp, x_mp, xd_mp, 0, pmp, conv_mp)
    print(f"  Euler residual on the 50-digit orbit: {mp.nstr(mp.norm(res_e), 3)}")
    mu_ref = multipliers(A_e, period)
    # the same at the orbit rounded to double (input rounding alone)
    _, A_ein, _ = A_of(fe_mp, [mp.mpf(e) for e in x_d], [mp.mpf(e) for e in xd_d], 0, pmp,
                       conv_mp)
    mu_ein = multipliers(A_ein, period)
    # the C kernels of libusm (double)
    lib = ctypes.CDLL(os.path.join(build, "libusm.so"))
    Dn = ctypes.c_double * 64
    xc, vc = (ctypes.c_double * 7)(*x_d), (ctypes.c_double * 7)(*xd_d)
    pc = (ctypes.c_double * len(pdouble))(*pdouble)
    out_m, out_r, out_m2 = Dn(), Dn(), Dn()
    getattr(lib, f"usm_{name}_mass")(xc, pc, out_m)
    getattr(lib, f"usm_{name}_jac_rhs")(xc, ctypes.c_double(0), pc, out_r)
    getattr(lib, f"usm_{name}_jac_mass")(xc, vc, pc, out_m2)
    Mc = mp.matrix(7, 7)
    Jc = mp.matrix(7, 7)
    for i in range(7):
        for j in range(7):
            Mc[i, j] = out_m[7 * i + j]
            Jc[i, j] = out_r[7 * i + j] - out_m2[7 * i + j]
    A_c = mp.inverse(Mc) * Jc
    mu_c = multipliers(A_c, period)
    Tm = Dn()
    getattr(lib, f"usm_{name}_tangent_map")(xc, pc, Tm)
    S = mp.matrix(7, 7)
    for i in range(7):
        for j in range(7):
            S[i, j] = Tm[7 * i + j]

    # 2. tilt-vector coordinates
    states, mass, rhs, v = tilt_model(assumptions["contact"])
    th, al = u
    a, b = mp.sin(th) * mp.sin(al), -mp.sin(th) * mp.cos(al)
    chid = OMEGA_mp = 2 * mp.pi * pmp[pnames.index("f")]
    chid = OMEGA_mp * (1 - 1 / mp.cos(th))
    y_mp = [a, b, mp.mpf(0), 0, 0, chid, x_mp[6]]
    yd_mp = [0, 0, chid, 0, 0, 0, 0]
    ft_mp, ft_d = linearisation_fns(states, mass, rhs, v)
    M_t, A_t, res_t = A_of(ft_mp, y_mp, yd_mp, 0, pmp, conv_mp)
    _, _, res_t2 = A_of(ft_mp, y_mp, yd_mp, mp.mpf("0.37") * period, pmp, conv_mp)
    print(f"  tilt residual on the 50-digit orbit: {mp.nstr(mp.norm(res_t), 3)} "
          f"(t = 0.37 T: {mp.nstr(mp.norm(res_t2), 3)})")
    mu_t = multipliers(A_t, period)
    print(f"  multipliers, Euler vs tilt (50 digits): {mp.nstr(match_err(mu_t, mu_ref), 3)}")
    y_d = [float(e) for e in y_mp]
    yd_d = [float(e) for e in yd_mp]
    _, A_tin, _ = A_of(ft_mp, [mp.mpf(e) for e in y_d], [mp.mpf(e) for e in yd_d], 0, pmp,
                       conv_mp)
    mu_tin = multipliers(A_tin, period)
    M_td, A_td, _ = A_of(ft_d, y_d, yd_d, 0.0, pdouble, conv_double)
    mu_td = multipliers(A_td, period)
    _, A_ed, _ = A_of(fe_d, x_d, xd_d, 0.0, pdouble, conv_double)
    mu_ed = multipliers(A_ed, period)

    def digits(err):
        return float(-mp.log10(err)) if err > 0 else 50.0

    print("  multipliers (50 digits):", ", ".join(mp.nstr(z, 17) for z in mu_ref))
    print("  correct digits (worst multiplier, absolute error):")
    rows = [("Euler, 50-digit A at the orbit rounded to double", mu_ein),
            ("Euler, C kernels (double)", mu_c),
            ("Euler, sympy expressions in double", mu_ed),
            ("tilt, 50-digit A at the orbit rounded to double", mu_tin),
            ("tilt, sympy expressions in double", mu_td)]
    for label, mu in rows:
        print(f"    {label:52s} {digits(match_err(mu, mu_ref)):5.2f}")
    # mpmath adds guard bits inside expm and eig: this is not double, only the
    # error of the 53-bit input G carried through (an optimistic bound).
    print("  exp(T G) then eig, in mpmath at 53-bit working precision (guard bits inside):")
    Sinv = mp.inverse(S)
    for label, G in (("Euler coordinates, C kernels", A_c),
                     ("Euler, tangent-map coordinates, C kernels", S * A_c * Sinv),
                     ("tilt coordinates, double", A_td)):
        print(f"    {label:52s} {pipeline53(G, period, mu_ref):5.2f}   "
              f"|T G|_1 = {mp.nstr(mp.mnorm(G * period, 1), 3)}")
    # 3. conditioning
    Phi_e = mp.expm(A_e * period)
    Phi_t = mp.expm(A_t * period)
    print(f"  cond(M): Euler {mp.nstr(svd_cond(M_e), 3)}, tilt {mp.nstr(svd_cond(M_t), 3)}")
    print(f"  |Phi|_2: Euler {mp.nstr(norm2(Phi_e), 3)}, Euler in tangent-map coordinates "
          f"{mp.nstr(norm2(S * Phi_e * mp.inverse(S)), 3)}, tilt {mp.nstr(norm2(Phi_t), 3)}")


if __name__ == "__main__":
    main()
