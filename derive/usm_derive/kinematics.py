"""z-x-z Euler-angle kinematics of the stator (paper, section 2, Fig. 5, Table 1).

Frames: N (X,Y,Z) inertial; A = N rotated by phi about Z; B = A rotated by
theta about x1; K (body) = B rotated by psi about z2.  A matrix ``C_XY`` maps
components in frame Y to components in frame X.
"""
import sympy as sp


def rot_z(a):
    """Components in the rotated frame -> components in the parent frame."""
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0],
                      [sp.sin(a), sp.cos(a), 0],
                      [0, 0, 1]])


def rot_x(a):
    return sp.Matrix([[1, 0, 0],
                      [0, sp.cos(a), -sp.sin(a)],
                      [0, sp.sin(a), sp.cos(a)]])


def simplify_entries(m):
    """trigsimp entry by entry: used only on small pieces (3x3 tensors)."""
    return m.applyfunc(sp.trigsimp)


class Kinematics:
    """Rotation matrices, angular velocity and contact point of the stator.

    q = (phi, theta, psi) are functions of time ``t``; the contact point is
    r_c = R e_y2 + H e_z2, the highest point of the tilted stator (fixed in B).
    """

    def __init__(self, t, phi, theta, psi, R, H):
        self.t = t
        self.phi, self.theta, self.psi = phi, theta, psi
        self.C_NA = rot_z(phi)
        self.C_AB = rot_x(theta)
        self.C_BK = rot_z(psi)
        # omega = phidot e_Z + thetadot e_x1 + psidot e_z2, components in B
        e_Z_in_B = self.C_AB.T * sp.Matrix([0, 0, 1])
        self.omega_B = (phi.diff(t) * e_Z_in_B
                        + theta.diff(t) * sp.Matrix([1, 0, 0])
                        + psi.diff(t) * sp.Matrix([0, 0, 1]))
        self.omega_A = self.C_AB * self.omega_B
        self.omega_K = self.C_BK.T * self.omega_B
        # angular velocity of frame A itself (phidot e_Z)
        self.frame_A_rate = sp.Matrix([0, 0, phi.diff(t)])
        self.r_c_A = self.C_AB * sp.Matrix([0, R, H])
        self.R_star = self.r_c_A[1]          # R cos(theta) - H sin(theta)
        self.Z = self.r_c_A[2]               # R sin(theta) + H cos(theta)
        # velocity of the stator's material point at the contact location
        self.v_c = self.omega_A.cross(self.r_c_A)[0]
        # the tilt as a rotation vector, theta e_x1, and the nodal line e_x1, in A
        self.tilt_vector_A = sp.Matrix([theta, 0, 0])
        self.e_x1_A = sp.Matrix([1, 0, 0])

    def housing_tilt_vector(self):
        """Tilt of the stator as a rotation vector in the housing frame N.

        The axis e_z2 leaves e_Z by the rotation theta about the nodal line
        e_Z x e_z2 / |e_Z x e_z2| (= e_x1): rho = theta * that unit vector, for
        finite rotations (no small-angle step).  It comes out as
        theta (cos phi, sin phi, 0): psi does not enter.
        """
        e_z2_N = self.C_NA * self.C_AB * sp.Matrix([0, 0, 1])
        nodal = sp.Matrix([0, 0, 1]).cross(e_z2_N)
        rho = nodal * self.theta / sp.sin(self.theta)
        if any(sp.sin(self.theta) in e.atoms(sp.sin) for e in rho):
            raise RuntimeError("housing tilt vector did not reduce")
        return rho

    def tensor_in_A_from_K(self, diag):
        """A body-fixed diagonal tensor (principal axes of K) in frame A."""
        # simplified in B first: for an axisymmetric stator psi drops out there
        tensor_B = simplify_entries(self.C_BK * sp.diag(*diag) * self.C_BK.T)
        return self.C_AB * tensor_B * self.C_AB.T

    def tensor_in_A_from_N(self, diag):
        """A tensor diagonal in the inertial frame N, seen in frame A."""
        return simplify_entries(self.C_NA.T * sp.diag(*diag) * self.C_NA)


def skew(v):
    """[v]x: skew(v) * w = v x w."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


class TiltKinematics:
    """Tilt-vector kinematics of the stator, regular at theta = 0.

    The same stator as ``Kinematics``, described without Euler angles.  Frame
    A's role (the frame whose components the rows are written in) is played by
    the co-rotating frame C = N turned by Omega t about Z.  Coordinates: the
    stator axis e_z2 in frame C, (a, b, sqrt(1 - a^2 - b^2)), and the spin
    angle chi.  The orientation is R = R_tilt(a, b) rot_z(chi) in frame N,
    with the tilt rotation (e_Z to e_z2 about the nodal line e_x1) written
    R_tilt = I + K + K^2 / (1 + cos theta), K = [e_Z x e_z2]x: no division by
    sin theta.  In Euler angles a + i b = sin(theta) exp(i (phi - Omega t - pi/2))
    and chi = phi + psi (``from_euler``).  The attributes are those of
    ``Kinematics`` (components in frame C where that names frame A), so the
    steps of the derivation use either without knowing which.

    The contact point stays singular at theta = 0 (docs/coordinates.md): e_x1
    is the unit vector of e_Z x e_z2, which has no limit there.
    """

    def __init__(self, t, a, b, chi, R, H, Omega):
        self.t, self.Omega = t, Omega
        self.a, self.b, self.chi = a, b, chi
        self.sin_theta = s = sp.sqrt(a ** 2 + b ** 2)
        self.cos_theta = c = sp.sqrt(1 - a ** 2 - b ** 2)
        self.theta = sp.asin(s)
        n = self.e_z2 = sp.Matrix([a, b, c])                 # stator axis, frame C
        k = sp.Matrix([-b, a, 0])                            # e_Z x e_z2 = sin(theta) e_x1
        K = skew(k)
        self.C_tilt = sp.eye(3) + K + K * K / (1 + c)         # e_Z -> e_z2 about e_x1
        self.C_NA = rot_z(Omega * t)                          # frame C in N
        W = self.C_tilt.diff(t) * self.C_tilt.T
        tilt_rate = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
        # omega = vee(R_N' R_N^T) + chi' e_z2 with R_N = C_NA C_tilt C_NA^T:
        # components in C, Omega (e_Z - e_z2) + vee(C_tilt' C_tilt^T) + chi' e_z2
        self.omega_A = (Omega * (sp.Matrix([0, 0, 1]) - n) + tilt_rate + chi.diff(t) * n)
        self.frame_A_rate = sp.Matrix([0, 0, Omega])
        e_x1 = self.e_x1_A = k / s
        e_y1 = sp.Matrix([0, 0, 1]).cross(e_x1)
        e_y2 = n.cross(e_x1)
        self.r_c_A = R * e_y2 + H * n                         # highest point of the stator
        self.R_star = self.r_c_A.dot(e_y1)
        self.Z = self.r_c_A[2]
        self.v_c = self.omega_A.cross(self.r_c_A).dot(e_x1)
        # theta e_x1 = theta / sin(theta) k, with theta / sin(theta) =
        # 1 / sinc(asin s): finite at theta = 0
        self.tilt_vector_A = k / sp.sinc(self.theta)

    def tensor_in_A_from_K(self, diag):
        """A body-fixed diagonal tensor (principal axes of K) in frame C."""
        if diag[0] == diag[1]:
            return self.C_tilt * sp.diag(*diag) * self.C_tilt.T
        spin = rot_z(self.chi - self.Omega * self.t)
        return self.C_tilt * spin * sp.diag(*diag) * spin.T * self.C_tilt.T

    def tensor_in_A_from_N(self, diag):
        """A tensor diagonal in the inertial frame N, seen in frame C."""
        return simplify_entries(self.C_NA.T * sp.diag(*diag) * self.C_NA)

    @staticmethod
    def from_euler(euler_kin, Omega, t):
        """(a, b, chi) of the z-x-z Euler angles of ``euler_kin``: e_z2 turned
        back by Omega t, and chi = phi + psi."""
        n_N = euler_kin.C_NA * euler_kin.C_AB * sp.Matrix([0, 0, 1])
        n_C = (rot_z(Omega * t).T * n_N).applyfunc(lambda e: sp.simplify(sp.expand_trig(e)))
        return [n_C[0], n_C[1], euler_kin.phi + euler_kin.psi]
