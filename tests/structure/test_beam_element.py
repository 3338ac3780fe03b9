"""The 3-D beam element alone: stiffness, mass and rotation against textbook closed forms.

References are closed forms written out in the tests (Przemieniecki, Theory of Matrix Structural
Analysis, 1968, ch. 5 and 11; any strength-of-materials text for the cantilever), not the code's
own output. Tolerances are round-off sized (1e-12 relative) where the element is exact.
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.structure.beam import (
    DOFS_LATERAL,
    DOFS_VERTICAL,
    element_mass,
    element_stiffness,
    rotation,
    section_mass,
    shear_parameter,
    to_global,
)

E, G, A, IY, IZ, J = 3.0e10, 1.2e10, 2.0, 0.4, 0.9, 0.3
L = 2.5


def _cantilever(k: np.ndarray, load: np.ndarray) -> np.ndarray:
    """Node 1 clamped, the load on node 2: the 6 DOFs of node 2."""
    return np.linalg.solve(k[6:, 6:], load)


@pytest.mark.parametrize("kappa", [0.0, 0.5])
def test_cantilever_tip_displacements_are_exact(kappa):
    """One element clamped at node 1, unit loads at node 2 (Euler-Bernoulli and Timoshenko).

    Closed forms: axial P L / (E A); torsion T L / (G J); bending tip deflection
    P L^3 / (3 E I) + P L / (G A_s) and tip rotation P L^2 / (2 E I), each plane with its own I
    (I_z for v along y_l, I_y for w along z_l, with ry = -dw/dx). The two-node element with the
    interdependent (Timoshenko) interpolation is exact for end loads, so the tolerance is round-off.
    """
    a_s = kappa * A
    k = element_stiffness(L, E, G, A, IY, IZ, J, a_s)
    shear = L / (G * a_s) if a_s > 0 else 0.0
    u = _cantilever(k, np.array([1.0, 0, 0, 0, 0, 0]))
    assert u[0] == pytest.approx(L / (E * A), rel=1e-12)
    u = _cantilever(k, np.array([0, 0, 0, 1.0, 0, 0]))
    assert u[3] == pytest.approx(L / (G * J), rel=1e-12)
    u = _cantilever(k, np.array([0, 1.0, 0, 0, 0, 0]))  # lateral force along y_l
    assert u[1] == pytest.approx(L**3 / (3 * E * IZ) + shear, rel=1e-12)
    assert u[5] == pytest.approx(L**2 / (2 * E * IZ), rel=1e-12)
    u = _cantilever(k, np.array([0, 0, 1.0, 0, 0, 0]))  # force along z_l
    assert u[2] == pytest.approx(L**3 / (3 * E * IY) + shear, rel=1e-12)
    assert u[4] == pytest.approx(-(L**2) / (2 * E * IY), rel=1e-12)


def test_stiffness_has_the_six_rigid_body_modes_in_its_null_space():
    """K r = 0 for the three translations and three small rotations of the element as a rigid
    body (node positions (0,0,0) and (L,0,0)); and K is symmetric. Round-off tolerance."""
    k = element_stiffness(L, E, G, A, IY, IZ, J, 0.3 * A)
    assert np.allclose(k, k.T, rtol=0, atol=1e-6 * np.abs(k).max())
    pos = np.array([[0.0, 0, 0], [L, 0, 0]])
    for i in range(6):
        r = np.zeros(12)
        for n in range(2):
            if i < 3:
                r[6 * n + i] = 1.0
            else:
                w = np.eye(3)[i - 3]
                r[6 * n : 6 * n + 3] = np.cross(w, pos[n])
                r[6 * n + 3 : 6 * n + 6] = w
        assert np.abs(k @ r).max() < 1e-9 * np.abs(k).max()


def test_euler_bernoulli_mass_is_the_textbook_consistent_mass():
    """phi = 0: each bending plane gives m L / 420 [156, 22L, 54, -13L; 22L, 4L^2, 13L, -3L^2; ...]
    (the rotation sign flipped in the x-z plane, ry = -dw/dx); axial m L / 6 [2, 1; 1, 2]; torsion
    I_p L / 6 [2, 1; 1, 2]. Exact quadrature: round-off tolerance."""
    m, ip = 3.0e3, 7.0e3
    mm = element_mass(L, section_mass(m, ip))
    ref = m * L / 420 * np.array([
        [156, 22 * L, 54, -13 * L],
        [22 * L, 4 * L * L, 13 * L, -3 * L * L],
        [54, 13 * L, 156, -22 * L],
        [-13 * L, -3 * L * L, -22 * L, 4 * L * L],
    ])
    s = np.array([1.0, -1.0, 1.0, -1.0])
    tol = 1e-12 * np.abs(ref).max()
    assert np.abs(mm[np.ix_(DOFS_LATERAL, DOFS_LATERAL)] - ref).max() < tol
    assert np.abs(mm[np.ix_(DOFS_VERTICAL, DOFS_VERTICAL)] - s[:, None] * ref * s).max() < tol
    assert np.allclose(mm[np.ix_([0, 6], [0, 6])], m * L / 6 * np.array([[2, 1], [1, 2]]), rtol=1e-12)
    assert np.allclose(mm[np.ix_([3, 9], [3, 9])], ip * L / 6 * np.array([[2, 1], [1, 2]]), rtol=1e-12)


def test_timoshenko_mass_is_przemienieckis():
    """phi > 0: translational consistent mass of the shear-flexible element (Przemieniecki 1968,
    eq. 11.41), e.g. m11 = m L (13/35 + 7 phi/10 + phi^2/3) / (1 + phi)^2. Round-off tolerance."""
    m = 2.0e3
    phi = shear_parameter(E, IZ, G, 0.4 * A, L)
    mm = element_mass(L, section_mass(m, 1.0), phi_y=phi)[np.ix_(DOFS_LATERAL, DOFS_LATERAL)]
    d = m * L / (1 + phi) ** 2
    expected = {
        (0, 0): (13 / 35 + 7 / 10 * phi + phi**2 / 3) * d,
        (0, 1): (11 / 210 + 11 / 120 * phi + phi**2 / 24) * L * d,
        (0, 2): (9 / 70 + 3 / 10 * phi + phi**2 / 6) * d,
        (0, 3): -(13 / 420 + 3 / 40 * phi + phi**2 / 24) * L * d,
        (1, 1): (1 / 105 + phi / 60 + phi**2 / 120) * L * L * d,
        (1, 3): -(1 / 140 + phi / 60 + phi**2 / 120) * L * L * d,
    }
    for (i, j), v in expected.items():
        assert mm[i, j] == pytest.approx(v, rel=1e-12)


def test_eccentric_mass_kinetic_energy():
    """A rigid-section motion (u, v, w, rx) of a mass m at (e, h) with polar moment I about its own
    centre has kinetic energy (m ((u)^2 + (v - h rx)^2 + (w + e rx)^2) + I rx^2) / 2 per unit
    velocity squared: the section matrix must reproduce it for random velocities."""
    m, ip, e, h = 1.2e4, 3.0e4, 2.5, 1.14
    s = section_mass(m, ip, e, h)
    rng = np.random.default_rng(3)
    for _ in range(5):
        u, v, w, t = rng.standard_normal(4)
        energy = 0.5 * (m * (u**2 + (v - h * t) ** 2 + (w + e * t) ** 2) + ip * t**2)
        q = np.array([u, v, w, t])
        assert 0.5 * q @ s @ q == pytest.approx(energy, rel=1e-12)


def test_rotation_of_girder_and_pier():
    """Convention: a girder along +x keeps the global axes; a pier along +z gets y_l = y_g and
    z_l = -x_g, so its I_z bends it in the global y-z plane (lateral). Rows orthonormal."""
    r = rotation(np.zeros(3), np.array([3.0, 0, 0]))
    assert np.allclose(r, np.eye(3))
    r = rotation(np.zeros(3), np.array([0, 0, 5.0]))
    assert np.allclose(r, [[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    r = rotation(np.array([1.0, 2, 3]), np.array([2.0, 4, 5]))
    assert np.allclose(r @ r.T, np.eye(3)) and np.linalg.det(r) == pytest.approx(1.0)
    with pytest.raises(ValueError):
        rotation(np.zeros(3), np.zeros(3))


def test_pier_stiffness_in_global_axes():
    """A vertical cantilever element (node 1 clamped at the origin, node 2 at z = L): a global
    lateral force F_y deflects it by F L^3 / (3 E I_z), a longitudinal F_x by F L^3 / (3 E I_y),
    and a vertical F_z shortens it by F L / (E A). Exact: round-off tolerance."""
    k = to_global(element_stiffness(L, E, G, A, IY, IZ, J), rotation(np.zeros(3), np.array([0, 0, L])))
    assert _cantilever(k, np.array([0, 1.0, 0, 0, 0, 0]))[1] == pytest.approx(L**3 / (3 * E * IZ), rel=1e-12)
    assert _cantilever(k, np.array([1.0, 0, 0, 0, 0, 0]))[0] == pytest.approx(L**3 / (3 * E * IY), rel=1e-12)
    assert _cantilever(k, np.array([0, 0, 1.0, 0, 0, 0]))[2] == pytest.approx(L / (E * A), rel=1e-12)
