"""Model.fit against an independent optimizer: SciPy's least_squares on the
package's steady() (finite-difference Jacobian, its own covariance) reaches
the same minimum and the same standard errors; data given as a mapping equal
the same data from a file; bad data raises ValueError naming the column."""
import math
import os

import pytest

import usm

scipy_optimize = pytest.importorskip("scipy.optimize")
np = pytest.importorskip("numpy")

DATA = os.path.join(os.path.dirname(__file__), "..", "cli", "fit", "speed.csv")
RPM = 2 * math.pi / 60


def read_data():
    rows = [l.strip().split(",") for l in open(DATA) if l.strip() and not l.startswith("#")]
    head, body = rows[0], [[float(v) for v in r] for r in rows[1:]]
    assert head == ["f [kHz]", "T [mNm]", "speed [rpm]", "sigma_speed [rpm]"]
    return head, body


def test_same_minimum_as_scipy():
    m = usm.Model("4dof")
    r = m.fit(DATA, ["c_r", "kappa"], starts=1)
    est = r["estimates"]
    _, body = read_data()

    def residuals(z):
        c_r, kappa = math.exp(z[0]), math.exp(z[1])
        out = []
        for f, T, rpm, sig in body:
            s = m.with_params(c_r=c_r, kappa=kappa, f=f * 1e3, T=T * 1e-3).steady()
            out.append((-s.rotor_speed - rpm * RPM) / (sig * RPM))
        return np.array(out)

    z0 = [math.log(m.parameters["c_r"].value * 1.1), math.log(m.parameters["kappa"].value * 0.9)]
    sol = scipy_optimize.least_squares(residuals, z0, jac="3-point", method="lm",
                                       xtol=1e-14, ftol=1e-14, gtol=1e-14)
    J = sol.jac
    cov = np.linalg.inv(J.T @ J)  # sigmas given: no rescaling
    for j, name in enumerate(["c_r", "kappa"]):
        p_scipy = math.exp(sol.x[j])
        se_scipy = p_scipy * math.sqrt(cov[j, j])
        e = est[name]
        assert abs(e["estimate"] - p_scipy) <= 1e-3 * e["standard_error"], (name, e, p_scipy)
        assert abs(e["standard_error"] / se_scipy - 1) < 0.05, (name, e, se_scipy)
    assert abs(r["chi2"] - 2 * sol.cost) < 1e-6 * r["chi2"]


def test_mapping_equals_file():
    head, body = read_data()
    cols = {h: [row[k] for row in body] for k, h in enumerate(head)}
    m = usm.Model("4dof")
    a = m.fit(cols, "c_r", starts=1).to_dict()
    b = m.fit(DATA, "c_r", starts=1).to_dict()
    assert a["estimates"] == b["estimates"]


def test_bad_data():
    m = usm.Model("4dof")
    with pytest.raises(ValueError, match="speed: the unit"):
        m.fit({"f [Hz]": [37000, 38000], "speed [N]": [11, 10]}, "c_r")
