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
