"""The 3-D two-node beam element: 6 DOF per node, Euler-Bernoulli or Timoshenko, consistent mass.

Local axes: x_l along the element from node 1 to node 2, y_l and z_l the principal axes of the
section. Local DOF order per node: (u, v, w, rx, ry, rz): displacements along x_l, y_l, z_l and
rotations about them; the element vector is (node 1, node 2), 12 entries.

Bending in the x_l-y_l plane (v, rz, rz = dv/dx for Euler-Bernoulli) uses ``I_z``; bending in
the x_l-z_l plane (w, ry, ry = -dw/dx) uses ``I_y``. Torsion uses ``G J``; axial ``E A``.

Interpolation (shared by the mass matrix and the mode-shape evaluation along the girder):
axial u and twist rx linear; v and w cubic. With shear flexibility (Timoshenko,
``shear_area_factor > 0``) the cubic is the interdependent interpolation that solves the static
Timoshenko equations exactly (Reddy 1997; Przemieniecki 1968): nodal rotations are the section
rotations, and phi = 12 E I / (G A_s L^2). With phi = 0 it is the Hermite cubic.

The section mass is a 4 x 4 matrix over (u, v, w, rx) per unit length (:func:`section_mass`); an
eccentric mass (offset e, height h from the shear centre) couples v and w with the twist:
a point at (e, h) moves by dy = v - h rx, dz = w + e rx. Rotary inertia of bending (rho I) and the
longitudinal motion of an eccentric mass are neglected (slender girders; see the module tests).

Pure numpy, no state: every function returns new arrays.
"""

from __future__ import annotations

import numpy as np

# 4-point Gauss-Legendre rule on [0, 1]: exact for polynomials up to degree 7 (cubic x cubic = 6)
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
GAUSS_POINTS = 0.5 * (_GAUSS_X + 1.0)
GAUSS_WEIGHTS = 0.5 * _GAUSS_W

#: local DOF indices of the bending planes: (v1, rz1, v2, rz2) and (w1, ry1, w2, ry2)
DOFS_LATERAL = (1, 5, 7, 11)
DOFS_VERTICAL = (2, 4, 8, 10)
#: sign that turns the nodal rotation into the section slope of the plane: psi_v = rz, psi_w = -ry
SIGN_LATERAL = np.array([1.0, 1.0, 1.0, 1.0])
SIGN_VERTICAL = np.array([1.0, -1.0, 1.0, -1.0])


def shear_parameter(E: float, I: float, G: float, shear_area: float, length: float) -> float:
    """phi = 12 E I / (G A_s L^2); 0 (Euler-Bernoulli) when ``shear_area`` is 0."""
    if shear_area <= 0.0:
        return 0.0
    return 12.0 * E * I / (G * shear_area * length**2)


def cubic_coefficients(length: float, phi: float = 0.0) -> np.ndarray:
    """Power-series coefficients of the bending interpolation of one plane.

    Returns C (4 x 4) such that, with xi = x / L in [0, 1] and the nodal vector
    d = (v1, psi1, v2, psi2) (displacements and section rotations of the plane),
    v(xi) = sum_p xi^p (C @ d)[p]. phi = 0 gives the Hermite cubic.

    Derivation: the static Timoshenko beam without distributed load has a constant shear force
    Q = -E I v''', so v is cubic, v = b0 + b1 xi + b2 xi^2 + b3 xi^3, and the section rotation is
    psi = v' - Q / (G A_s) = (b1 + 2 b2 xi + 3 b3 xi^2 + b3 phi / 2) / L. The four nodal values
    fix b; C is the inverse of that map.
    """
    L = float(length)
    a = np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0 / L, 0.0, 0.5 * phi / L],
            [1.0, 1.0, 1.0, 1.0],
            [0.0, 1.0 / L, 2.0 / L, (3.0 + 0.5 * phi) / L],
        ]
    )
    return np.linalg.inv(a)


def element_stiffness(
    length: float, E: float, G: float, area: float, I_y: float, I_z: float, J: float, shear_area: float = 0.0
) -> np.ndarray:
    """Local 12 x 12 stiffness matrix of a prismatic 3-D beam (Przemieniecki 1968, with shear).

    Parameters
    ----------
    length : element length L [m]
    E, G : Young's and shear modulus [N/m^2]
    area : cross-section area A [m^2] (axial stiffness E A)
    I_y : second moment for bending in the x_l-z_l plane (w, ry) [m^4]
    I_z : second moment for bending in the x_l-y_l plane (v, rz) [m^4]
    J : torsion constant [m^4]
    shear_area : A_s = shear area factor * A [m^2]; 0 = Euler-Bernoulli (no shear deformation)

    Returns
    -------
    (12, 12) symmetric positive semi-definite matrix (6 rigid-body modes in its null space).
    """
    L = float(length)
    k = np.zeros((12, 12))
    ea, gj = E * area / L, G * J / L
    k[np.ix_([0, 6], [0, 6])] = ea * np.array([[1.0, -1.0], [-1.0, 1.0]])
    k[np.ix_([3, 9], [3, 9])] = gj * np.array([[1.0, -1.0], [-1.0, 1.0]])
    for dofs, sign, inertia in ((DOFS_LATERAL, SIGN_LATERAL, I_z), (DOFS_VERTICAL, SIGN_VERTICAL, I_y)):
        phi = shear_parameter(E, inertia, G, shear_area, L)
        c = E * inertia / ((1.0 + phi) * L**3)
        kb = c * np.array(
            [
                [12.0, 6.0 * L, -12.0, 6.0 * L],
                [6.0 * L, (4.0 + phi) * L**2, -6.0 * L, (2.0 - phi) * L**2],
                [-12.0, -6.0 * L, 12.0, -6.0 * L],
                [6.0 * L, (2.0 - phi) * L**2, -6.0 * L, (4.0 + phi) * L**2],
            ]
        )
        k[np.ix_(dofs, dofs)] = sign[:, None] * kb * sign[None, :]
    return k


def section_mass(
    mass_per_length: float, rot_mass_per_length: float, offset: float = 0.0, height: float = 0.0
) -> np.ndarray:
    """Mass per unit length of a section as a 4 x 4 matrix over (u, v, w, rx).

    A mass m (polar moment I about its own centre) whose centre is at lateral ``offset`` e and
    ``height`` h from the shear centre moves by (u, v - h rx, w + e rx); its kinetic energy per
    length gives [[m, 0, 0, 0], [0, m, 0, -m h], [0, 0, m, m e], [0, -m h, m e, I + m (e^2 + h^2)]].
    Sections add (girder + added mass).
    """
    m, e, h = float(mass_per_length), float(offset), float(height)
    return np.array(
        [
            [m, 0.0, 0.0, 0.0],
            [0.0, m, 0.0, -m * h],
            [0.0, 0.0, m, m * e],
            [0.0, -m * h, m * e, float(rot_mass_per_length) + m * (e * e + h * h)],
        ]
    )


def interpolation_matrix(xi: float, length: float, phi_y: float = 0.0, phi_z: float = 0.0) -> np.ndarray:
    """N (4 x 12): (u, v, w, rx) at xi = x / L in [0, 1] from the 12 local element DOFs.

    ``phi_y`` is the shear parameter of the x_l-y_l plane (v, I_z), ``phi_z`` of the x_l-z_l plane.
    """
    n = np.zeros((4, 12))
    n[0, 0], n[0, 6] = 1.0 - xi, xi
    n[3, 3], n[3, 9] = 1.0 - xi, xi
    powers = np.array([1.0, xi, xi * xi, xi**3])
    for row, dofs, sign, phi in ((1, DOFS_LATERAL, SIGN_LATERAL, phi_y), (2, DOFS_VERTICAL, SIGN_VERTICAL, phi_z)):
        n[row, list(dofs)] = (powers @ cubic_coefficients(length, phi)) * sign
    return n


def element_mass(length: float, section: np.ndarray, phi_y: float = 0.0, phi_z: float = 0.0) -> np.ndarray:
    """Local 12 x 12 consistent mass matrix: integral of N^T S N over the element.

    Parameters
    ----------
    length : element length [m]
    section : (4, 4) section mass per length over (u, v, w, rx), see :func:`section_mass`
    phi_y, phi_z : shear parameters of the two bending planes (0: Euler-Bernoulli, which gives
        the textbook matrix m L / 420 [156, 22 L, 54, -13 L; ...] for each plane)

    Integrated exactly by 4-point Gauss quadrature (the integrand is a polynomial of degree 6).
    """
    m = np.zeros((12, 12))
    s = np.asarray(section, dtype=float)
    for xi, w in zip(GAUSS_POINTS, GAUSS_WEIGHTS):
        n = interpolation_matrix(xi, length, phi_y, phi_z)
        m += w * (n.T @ s @ n)
    m *= float(length)
    return 0.5 * (m + m.T)


def rotation(start: np.ndarray, end: np.ndarray, y_axis: np.ndarray | None = None) -> np.ndarray:
    """Rotation matrix R (3 x 3) whose rows are the local axes (x_l, y_l, z_l) in global coordinates.

    x_l points from ``start`` to ``end``. y_l is ``y_axis`` made orthogonal to x_l when given; by
    default y_l = z_g x x_l normalised (a horizontal girder along +x gets y_l = y_g, z_l = z_g),
    and for a vertical member (x_l = +z_g) y_l = y_g, z_l = -x_g: so a pier's I_z governs bending
    in the global y-z plane and I_y in the x-z plane. A local vector a_l = R a_g.
    """
    d = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(d))
    if length <= 0.0:
        raise ValueError("element of zero length")
    ex = d / length
    if y_axis is None:
        ref = np.array([0.0, 0.0, 1.0])
        if abs(ex @ ref) > 1.0 - 1e-9:
            ref = np.array([-1.0, 0.0, 0.0])
        ey = np.cross(ref, ex)
    else:
        ey = np.asarray(y_axis, dtype=float) - (np.asarray(y_axis, dtype=float) @ ex) * ex
    norm = float(np.linalg.norm(ey))
    if norm <= 1e-12:
        raise ValueError("y_axis parallel to the element")
    ey = ey / norm
    ez = np.cross(ex, ey)
    return np.vstack([ex, ey, ez])


def to_global(matrix_local: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """T^T A T with T = blockdiag(R, R, R, R): a 12 x 12 local element matrix in global axes."""
    t = np.kron(np.eye(4), rot)
    return t.T @ matrix_local @ t
