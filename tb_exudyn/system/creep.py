"""Linear wheel-rail creep forces of a wheelset (Kalker's linear theory), plain numpy.

What this module gives
----------------------
For one wheelset rolling at speed v along a straight track, the linear creep and gravitational
forces as matrices on the wheelset's coordinates and on the rail's motion at the contact
(:func:`creep_rows`), with the creep coefficients from the normal load and the contact geometry
(:func:`hertz_ellipse`, :func:`kalker_coefficients`, :func:`creep_coefficients`) or given as data.

Axes and signs (the project's): x along the track in the direction of travel, y lateral to the
left, z up; rx roll, rz yaw, right-handed. The left wheel sits at y = +b0, the right at -b0 (b0 half
the distance of the two contact points), the contact points r0 (rolling radius) below the axle.

Wheelset coordinates w = (y, rx, rz, x, ry) (:data:`WHEEL_COORDINATES`): the lateral-plane ones
first, lateral displacement of the axle centre [m], roll [rad] and yaw [rad] (the leading end
turned to the left for rz > 0), then the longitudinal-plane ones, the axle centre's longitudinal
displacement x [m] (from its place in the frame moving with the train at v) and the spin
perturbation ry [rad] (the wheelset turns at v / r0 + ry' about +y: forward rolling turns it about
+y, the contact point r0 below the axle then moves backwards relative to the axle). The contact
point at rail level moves laterally by y + r0 rx and longitudinally by x - r0 ry -/+ b0 rz (left /
right wheel).

Rail coordinates rho = (y_r, theta_r, psi_r) at the contact: the rail's lateral displacement at rail
level [m] (alignment irregularity plus the bridge's lateral motion), the roll of the rail plane
[rad] (cross-level angle plus the deck's roll) and the rail's yaw angle [rad], the slope
d y_r / dx of its line (alignment slope plus the bridge's lateral slope; for a beam without shear
deformation the deck's rotation about z). Their *material* rates (the rail at a fixed x) enter the
creepages; an irregularity is fixed in space and has none, only the bridge's motion does.

Creepages (Kalker's definition: rigid slip velocity of the wheel relative to the rail, divided by
v; linear, for small motions about steady rolling, as in Wickens' linear wheelset theory and
Garg & Dukkipati, "Dynamics of Railway Vehicle Systems", 1984; derived below):

    longitudinal, left / right wheel:
        xi_x = (x' - r0 ry') / v  -/+ [ lambda (y + r0 rx - y_r) / r0 + b0 (rz' - psi_r') / v ]
    lateral (both wheels):
        xi_y = (y' + r0 rx' - y_r') / v - rz
    spin, left / right wheel (optional):
        phi = (rz' - psi_r') / v  (the static parts -/+ delta0 / r0 cancel between the wheels)

Derivation. The wheel turns at the rate v / r0 + ry' about +y; a point r0 below the axle moves
by (v / r0 + ry') r0 backwards relative to the axle, which moves forward at v + x', so the wheel's
material point at the contact slips forward by x' - r0 ry' (the common longitudinal creepage of
both wheels: a wheelset rolling faster than its speed, ry' > x' / r0, slips backwards). The left
wheel rolls on the radius r0 + lambda e (e = y + r0 rx - y_r, the lateral displacement relative to
the rail at rail level, lambda the equivalent conicity), the right one on r0 - lambda e, so their
contact points slip forward by a further -/+ v lambda e / r0; the yaw rate moves the left contact
point by -b0 rz' along x. The wheel's rolling direction is turned by rz against the track, so its
contact point slips laterally by y' + r0 rx' - v rz. The rail's material velocity at the contact
(the bridge moving) is subtracted from both; the rail's yaw rate psi_r' turns the two rails'
contact points by -/+ b0 psi_r' along x. The rail's LONGITUDINAL velocity at the contact is
neglected: the deck's axial motion at rail level is not among the coupling's rail coordinates
(rho above), and the track is straight without a longitudinal irregularity, so nothing else moves
the rail along x. With these, a wheelset that follows a (slowly) curved rail exactly (y = y_r,
rz = psi_r, rolling at x' = r0 ry') has no lateral creepage and the longitudinal creepage -/+ b0
y_r'' of a curve. Gyroscopic terms of the spinning wheelset (I_wy v / r0 coupling roll and yaw
rates) are neglected, as in Wickens' linear wheelset.

Forces on the wheel (Kalker's linear law, f11 etc. per wheel, see :func:`creep_coefficients`):

    F_x = -f11 xi_x,    F_y = -f22 xi_y - f23 phi,    M_z = f23 xi_y - f33 phi

(the signs of the f23 terms as the linear-theory literature reproduces Kalker's [check]; they enter
only with the spin creepage switched on).

The rows of :func:`creep_rows`, all forces the rail exerts on the wheelset:

- ``force_y``: the lateral force at rail level, both wheels:
  -2 f22 xi_y - 2 f23 phi - K_gy e - W theta_r
  K_gy = W epsilon / b0 is the gravitational stiffness: the normal forces of the two wheels
  (together the axle load W) are tilted against the track plane by the contact-angle difference
  delta_L - delta_R = 2 epsilon e / b0 (epsilon the contact-angle parameter; for conical wheels on
  knife-edge rails the wheelset rolls by lambda e / b0 against the track and epsilon = lambda). The
  term -W theta_r is the same normal load tilted with the rail plane (cross-level or deck roll):
  it points down the slope.
- ``left.force_x``, ``right.force_x``: the longitudinal creep forces -f11 xi_x of each wheel,
  at the contact point: on the wheelset's x with lever 1, on its spin ry with -r0 (a force F_x
  r0 below the axle: moment -r0 F_x about +y) and on its yaw with -/+ b0. Their common part
  -f11 (x' - r0 ry') / v damps the wheelset's longitudinal motion against its spin; their
  antisymmetric part gives the yaw moment -2 b0 F_x,left of Wickens' model (traction and braking
  torques are not modelled: the axle carries no torque).
- ``moment_z``: the spin creep moments of both wheels and the gravitational yaw moment:
  2 f23 xi_y - 2 f33 phi - K_gpsi (rz - psi_r). K_gpsi is data (0 by default: neglected, as in
  Wickens' simplest model).

Each row is linear: f = -(K_w w + C_w w') + K_r rho + C_r rho'_mat, with C_w, C_r proportional to 1 / v.
It is applied to the wheelset as the generalised force Q_w = A_w^T f and to the rail as the
reaction Q_rho = -A_r^T f (virtual work: ``force_y`` acts at the contact point, y + r0 rx, and on
the rail's lateral displacement; a longitudinal force at the contact point (x - r0 ry -/+ b0 rz)
acts on x, ry and the yaw, and on the rail's yaw with the lever -/+ b0 (the rail's longitudinal
motion is neglected, above); ``moment_z`` on rz and psi_r).

The wheelset's roll from the rolling-radius difference (:func:`rolling_roll_terms`). The left wheel
rolls on r0 + lambda e, the right one on r0 - lambda e, so a wheelset whose wheels stay on the
rails rolls by lambda e / b0 against the rail plane. That roll is not a row of its own: it is the
vertical contact's geometry. A vertical contact row of the wheel on side s (+1 left, -1 right) at
the lever l (the row z + s l rx of the wheel's point over the rail) gets the wheel's height change
over the rail, -s kappa e with kappa = lambda l / b0, in its argument (stiff contacts then hold
rx = theta_r + lambda e / b0), and, by virtual work, the same map as its application: the normal
force N of the wheel acts on y with -s kappa N and on rx with -s kappa r0 N besides z and s l rx,
the lateral components of the normal forces at the inclined contacts (-lambda (N_L - N_R) with
l = b0). The rail gets the reactions (its lateral motion y_r enters e). The static parts of these
lateral components cancel between the two wheels; the lateral force of the static load tilted with
the roll is the gravitational stiffness K_gy e of ``force_y`` (with epsilon, the contact-angle
parameter, for profiles that are not conical), which therefore stays as it is. A roll moment alone
(the roll in the rows' argument, not in their application) leaves out the lateral components: the
linear critical speeds of the ICE creep cars then come out 5.7 % (motor car) and 7.4 % (trailer)
lower (docs/creep_design.md, section 8).

On straight track the rows split into two subsystems of the wheelset: the lateral plane (y, rx, rz
with the rail's y_r, theta_r, psi_r) and the longitudinal plane (x, ry): the common longitudinal
creep reaches only x and ry and no rail coordinate, the antisymmetric part only rz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import SettingError

#: wheelset coordinates of the rows (columns of K_w, C_w, A_w): the lateral plane, then x and the spin
WHEEL_COORDINATES: tuple[str, ...] = ("y", "rx", "rz", "x", "ry")
#: rail coordinates at the contact (columns of K_r, C_r, A_r)
RAIL_COORDINATES: tuple[str, ...] = ("y", "roll", "yaw")
#: the rows (forces of the rail on the wheelset)
ROWS: tuple[str, ...] = ("force_y", "left.force_x", "right.force_x", "moment_z")


# ============================================================================== Hertz contact
@dataclass(frozen=True)
class HertzContact:
    """The Hertz contact ellipse of one wheel on the rail.

    Attributes
    ----------
    a : semi-axis along the rolling direction x [m]
    b : semi-axis along the lateral direction y [m]
    p0 : maximum contact pressure [N/m^2]
    contact_modulus : E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [N/m^2]
    """

    a: float
    b: float
    p0: float
    contact_modulus: float


def contact_modulus(E: float, nu: float, E_rail: float | None = None, nu_rail: float | None = None) -> float:
    """E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) [N/m^2] (Johnson, Contact Mechanics, 1985, sec. 4.2);
    the rail's E, nu default to the wheel's."""
    E2 = E if E_rail is None else E_rail
    nu2 = nu if nu_rail is None else nu_rail
    return 1.0 / ((1.0 - nu * nu) / E + (1.0 - nu2 * nu2) / E2)


def wheel_rail_curvatures(
    rolling_radius: float, rail_transverse_radius: float, wheel_transverse_radius: float = math.inf,
) -> tuple[float, float]:
    """Relative curvatures (A along x, B along y) [1/m] of a wheel on a straight rail.

    A = 1/2 (1/r0), B = 1/2 (1/R_w + 1/R_r) (Johnson 1985, sec. 4.2, for principal planes that
    coincide: the wheel's and rail's axes are parallel). r0: rolling radius; R_r: the rail head's
    transverse (crown) radius; R_w: the wheel profile's transverse radius at the contact, positive
    when convex, negative when concave (a worn hollow tread), inf for a conical tread.
    """
    A = 0.5 / rolling_radius
    B = 0.5 * (1.0 / wheel_transverse_radius + 1.0 / rail_transverse_radius)
    if not (A > 0 and B > 0 and math.isfinite(A) and math.isfinite(B)):
        raise SettingError("wheel_rail_curvatures", "rail_transverse_radius", rail_transverse_radius,
                           "radii giving positive relative curvatures A = 1/(2 r0) and B = (1/R_w + 1/R_r)/2",
                           f"A = {A:g}, B = {B:g} 1/m")
    return A, B


def _series_coefficients(n: int = 80) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Power-series coefficients in m of K(m) - E(m) and E(m)/(1 - m) - K(m), both divided by pi/2.

    From K = pi/2 sum c_n^2 m^n and E = pi/2 sum c_n^2 m^n / (1 - 2n), c_n = (2n)! / (2^(2n) n!^2):
    K - E has the coefficients c_n^2 2n / (2n - 1) and E/(1 - m) - K the coefficients
    sum_{j<=n} c_j^2 / (1 - 2j) - c_n^2; both series have positive terms (no cancellation, unlike
    the difference of the two integrals for small m).
    """
    c2 = np.ones(n)
    for k in range(1, n):
        c2[k] = c2[k - 1] * ((2 * k - 1) / (2 * k)) ** 2
    j = np.arange(n)
    k_minus_e = c2 * 2 * j / np.where(j == 0, 1, 2 * j - 1)
    e_over = np.cumsum(c2 / (1 - 2 * j)) - c2
    return k_minus_e, e_over


_K_MINUS_E, _E_OVER_1M_MINUS_K = _series_coefficients()


def _elliptic_differences(m: float) -> tuple[float, float]:
    """(K(m) - E(m)) / m and (E(m)/(1 - m) - K(m)) / m, both pi/4 at m = 0: power series below
    m = 0.1 (terms below 1e-78), the complete elliptic integrals above (where the differences are
    large)."""
    if m < 0.1:
        powers = m ** np.arange(_K_MINUS_E.size - 1)
        return 0.5 * math.pi * float(_K_MINUS_E[1:] @ powers), 0.5 * math.pi * float(_E_OVER_1M_MINUS_K[1:] @ powers)
    from scipy.special import ellipe, ellipk  # on first use (creep cars): scipy.special costs 0.2 s at import

    K, E = float(ellipk(m)), float(ellipe(m))
    return (K - E) / m, (E / (1.0 - m) - K) / m


def _ellipse_ratio(m: float) -> float:
    """B/A of the Hertz ellipse of eccentricity e^2 = m (a the major semi-axis, along A's direction)."""
    kme, eok = _elliptic_differences(m)
    return eok / kme


def hertz_ellipse(normal_load: float, A: float, B: float, E_star: float) -> HertzContact:
    """Hertz's contact ellipse under the normal load P [N] for relative curvatures A (along x) and
    B (along y) [1/m] and the contact modulus E* [N/m^2].

    Johnson, Contact Mechanics (1985), sec. 3.5 and 4.2: with semi-axes a >= b, the eccentricity
    e^2 = 1 - b^2/a^2, K(e), E(e) the complete elliptic integrals and p0 = 3 P / (2 pi a b), the
    smaller and larger relative curvature A' <= B' satisfy

        A' = p0 b / (E* e^2 a^2) [K(e) - E(e)],   B' = p0 b / (E* e^2 a^2) [(a^2/b^2) E(e) - K(e)],

    so that B'/A' = [E(e) / (1 - e^2) - K(e)] / [K(e) - E(e)] and a^3 = 3 P [K(e) - E(e)] / (2 pi E* e^2 A'),
    where A' <= B' are the smaller and larger curvature: the major semi-axis lies along the
    direction of the smaller relative curvature. e follows from the ratio (monotonic in e; solved
    by Brent's method to machine precision; the differences of the elliptic integrals by their
    power series for small e, see :func:`_series_coefficients`), then a, b. For A = B (e = 0,
    (K - E)/e^2 = pi/4): the circle a^3 = 3 P R / (4 E*) with R = 1 / (2 A).
    """
    for key, val in (("normal_load", normal_load), ("A", A), ("B", B), ("E_star", E_star)):
        if not (math.isfinite(val) and val > 0):
            raise SettingError("hertz_ellipse", key, val, "a finite number > 0")
    small, large = min(A, B), max(A, B)
    ratio = large / small
    if ratio == 1.0:
        m = 0.0
    else:
        hi = 1.0 - 1e-15
        if _ellipse_ratio(hi) < ratio:
            raise SettingError("hertz_ellipse", "B/A", ratio, "a curvature ratio below 1e13", "ellipse too slender")
        from scipy.optimize import brentq  # on first use (creep cars): scipy.optimize costs 0.3 s at import

        m = brentq(lambda mm: _ellipse_ratio(mm) - ratio, 0.0, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps,
                   maxiter=500)
    kme_over_m = _elliptic_differences(m)[0]
    a_major = (3.0 * normal_load * kme_over_m / (2.0 * math.pi * E_star * small)) ** (1.0 / 3.0)
    a_minor = a_major * math.sqrt(1.0 - m)
    a, b = (a_major, a_minor) if A <= B else (a_minor, a_major)
    return HertzContact(a=float(a), b=float(b), p0=float(3.0 * normal_load / (2.0 * math.pi * a * b)),
                        contact_modulus=float(E_star))


# ============================================================================ Kalker's table
# Kalker's coefficients C11, C22, C23, C33 of the linear theory of rolling contact for elliptic
# contact areas, at Poisson's ratio nu = 0, 0.25, 0.5, for g = a/b = 0.1 ... 1.0 (rows of _A_LT_B)
# and g = b/a = 1.0 ... 0.1 (rows of _A_GT_B, a > b), a along the rolling direction.
# C11, C22, C23: Kalker, "Three-dimensional elastic bodies in rolling contact" (Kluwer, 1990),
# Table E.3, as tabulated in Vollebregt's CONTACT (m_hertz.f90, subroutine linrol).
# C33: the same table as reproduced in the railway literature (Kalker 1967 thesis, Table 4;
# Garg & Dukkipati 1984, Table 5.1) [check]: not read in a source available to us; only used
# when the spin creep moment is switched on.
_G = np.round(np.arange(1, 11) / 10.0, 10)
_A_LT_B = np.array([  # g = a/b: rows g = 0.1 .. 1.0; columns C11(nu=0, .25, .5), C22(...), C23(...), C33(...)
    [2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731, 6.42, 8.28, 11.7],
    [2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809, 3.46, 4.27, 5.66],
    [2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889, 2.49, 2.96, 3.72],
    [2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977, 2.02, 2.32, 2.77],
    [2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07, 1.74, 1.93, 2.22],
    [2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18, 1.56, 1.68, 1.86],
    [3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29, 1.43, 1.50, 1.60],
    [3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40, 1.34, 1.37, 1.42],
    [3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51, 1.27, 1.27, 1.27],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16],
])
_A_GT_B = np.array([  # g = b/a: rows g = 0.1 .. 1.0
    [10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0, 0.795, 0.526, 0.228],
    [6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89, 0.828, 0.601, 0.341],
    [5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01, 0.868, 0.674, 0.446],
    [4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70, 0.912, 0.747, 0.549],
    [4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96, 0.958, 0.819, 0.650],
    [4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50, 1.01, 0.892, 0.751],
    [3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18, 1.05, 0.965, 0.852],
    [3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94, 1.10, 1.04, 0.954],
    [3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77, 1.16, 1.11, 1.06],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16],
])
_NU = (0.0, 0.25, 0.5)


@dataclass(frozen=True)
class KalkerCoefficients:
    """Kalker's dimensionless linear creep coefficients (Kalker 1990, Table E.3)."""

    C11: float
    C22: float
    C23: float
    C33: float


def kalker_coefficients(nu: float, a_over_b: float) -> KalkerCoefficients:
    """Kalker's C11, C22, C23, C33 for Poisson's ratio nu and semi-axis ratio a/b (a along x).

    Interpolation in Kalker's table (see the module's table comment): linear in g = min(a/b, b/a)
    between the tabulated g = 0.1, 0.2, ..., 1.0, and in nu quadratic (Lagrange through nu = 0,
    0.25, 0.5) on the reciprocal 1/C, which is close to linear in nu (C11 ~ 1/(1 - nu) for a/b -> 0).
    At the tabulated points the table's values are returned exactly. Allowed: 0 <= nu <= 0.5 and
    0.1 <= a/b <= 10 (the table's range; no extrapolation).
    """
    if not (0.0 <= nu <= 0.5):
        raise SettingError("kalker_coefficients", "nu", nu, "0 <= nu <= 0.5 (Kalker's table)")
    if not (math.isfinite(a_over_b) and 0.1 - 1e-12 <= a_over_b <= 10.0 + 1e-10):
        raise SettingError("kalker_coefficients", "a_over_b", a_over_b, "0.1 <= a/b <= 10 (Kalker's table)")
    table, g = (_A_LT_B, a_over_b) if a_over_b <= 1.0 else (_A_GT_B, 1.0 / a_over_b)
    g = min(max(g, 0.1), 1.0)
    row = np.array([np.interp(g, _G, table[:, j]) for j in range(12)]).reshape(4, 3)
    n0, n1, n2 = _NU
    weights = np.array([
        (nu - n1) * (nu - n2) / ((n0 - n1) * (n0 - n2)),
        (nu - n0) * (nu - n2) / ((n1 - n0) * (n1 - n2)),
        (nu - n0) * (nu - n1) / ((n2 - n0) * (n2 - n1)),
    ])
    c = 1.0 / ((1.0 / row) @ weights)
    for j, w in enumerate(weights):  # a tabulated nu: the table's value itself (no round-off)
        if w == 1.0:
            c = row[:, j]
    return KalkerCoefficients(*(float(v) for v in c))


# ====================================================================== creep coefficients
@dataclass(frozen=True)
class CreepCoefficients:
    """Linear creep coefficients of ONE wheel: F_x = -f11 xi_x, F_y = -f22 xi_y - f23 phi,
    M_z = f23 xi_y - f33 phi (xi dimensionless, phi [1/m]).

    Attributes
    ----------
    f11 : longitudinal [N]
    f22 : lateral [N]
    f23 : lateral/spin [N m]
    f33 : spin [N m^2]
    """

    f11: float
    f22: float
    f23: float = 0.0
    f33: float = 0.0

    def scaled(self, factor: float) -> "CreepCoefficients":
        """All coefficients times ``factor`` (e.g. a reduction for a real, contaminated contact)."""
        return CreepCoefficients(self.f11 * factor, self.f22 * factor, self.f23 * factor, self.f33 * factor)


def creep_coefficients(G: float, a: float, b: float, C: KalkerCoefficients) -> CreepCoefficients:
    """f11 = G a b C11, f22 = G a b C22, f23 = G (a b)^1.5 C23, f33 = G (a b)^2 C33 (Kalker's
    normalisation of his table; Kalker 1990, appendix E); G the combined shear modulus
    2 G1 G2 / (G1 + G2) [N/m^2], a, b the semi-axes along x and y [m]."""
    ab = a * b
    return CreepCoefficients(f11=float(G * ab * C.C11), f22=float(G * ab * C.C22), f23=float(G * ab**1.5 * C.C23),
                             f33=float(G * ab * ab * C.C33))


def hertz_creep_coefficients(
    normal_load: float, rolling_radius: float, rail_transverse_radius: float,
    wheel_transverse_radius: float = math.inf, E: float = 2.1e11, nu: float = 0.3,
) -> tuple[CreepCoefficients, HertzContact]:
    """Creep coefficients of one wheel (wheel and rail of the same steel, E [N/m^2], nu) from its
    normal load [N] and the contact geometry [m] (see :func:`wheel_rail_curvatures`):
    Hertz's ellipse, Kalker's C_ij at its a/b and G = E / (2 (1 + nu))."""
    A, B = wheel_rail_curvatures(rolling_radius, rail_transverse_radius, wheel_transverse_radius)
    ellipse = hertz_ellipse(normal_load, A, B, contact_modulus(E, nu))
    C = kalker_coefficients(nu, ellipse.a / ellipse.b)
    return creep_coefficients(E / (2.0 * (1.0 + nu)), ellipse.a, ellipse.b, C), ellipse


# ============================================================================ wheelset rows
@dataclass(frozen=True)
class WheelsetContact:
    """The linear contact data of one wheelset on the rails.

    Attributes
    ----------
    coefficients : creep coefficients of each wheel
    rolling_radius : r0 [m]
    half_contact_distance : b0, half the lateral distance of the two contact points [m]
    conicity : lambda, the equivalent conicity (r_left - r_right = 2 lambda e) [-]
    axle_load : W, the static normal load of both wheels together [N]
    contact_angle_parameter : epsilon (delta_L - delta_R = 2 epsilon e / b0, against the track
        plane) [-]; None: lambda (conical wheels on knife-edge rails)
    gravitational_yaw_stiffness : K_gpsi [N m/rad] (0: neglected)
    spin : include the spin creepage (f23, f33 terms)
    """

    coefficients: CreepCoefficients
    rolling_radius: float
    half_contact_distance: float
    conicity: float
    axle_load: float
    contact_angle_parameter: float | None = None
    gravitational_yaw_stiffness: float = 0.0
    spin: bool = False

    @property
    def gravitational_stiffness(self) -> float:
        """K_gy = W epsilon / b0 [N/m]."""
        eps = self.conicity if self.contact_angle_parameter is None else self.contact_angle_parameter
        return self.axle_load * eps / self.half_contact_distance


@dataclass(frozen=True)
class CreepRows:
    """The linear creep rows of one wheelset at speed v (forces of the rail on the wheelset).

    f = -(K_w w + C_w w') + K_r rho + C_r rho'_mat,  Q_w = A_w^T f,  Q_rho = -A_r^T f.

    Attributes
    ----------
    rows : row names (:data:`ROWS`)
    K_w, C_w, A_w : (n_rows, 5) on the wheelset coordinates (y, rx, rz, x, ry) (:data:`WHEEL_COORDINATES`)
    K_r, C_r, A_r : (n_rows, 3) on the rail coordinates (y_r, theta_r, psi_r)
    speed : v [m/s]
    """

    rows: tuple[str, ...]
    K_w: NDArray[np.float64]
    C_w: NDArray[np.float64]
    A_w: NDArray[np.float64]
    K_r: NDArray[np.float64]
    C_r: NDArray[np.float64]
    A_r: NDArray[np.float64]
    speed: float

    def forces(self, w: ArrayLike, w_dot: ArrayLike, rho: ArrayLike = (0.0, 0.0, 0.0),
               rho_dot: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
        """The row forces f [N, N m] for wheelset state (w, w') (5 entries each, (y, rx, rz, x, ry))
        and rail motion (rho, rho'_mat) (3 entries each)."""
        w, wd, r, rd = (np.asarray(a, dtype=float) for a in (w, w_dot, rho, rho_dot))
        return -(self.K_w @ w + self.C_w @ wd) + self.K_r @ r + self.C_r @ rd

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """(5, 5) stiffness of the wheelset's equations of motion on (y, rx, rz, x, ry) (left-hand
        side, rail at rest): M w'' + C w' + K w = 0 with K = A_w^T K_w (not symmetric)."""
        return self.A_w.T @ self.K_w

    @property
    def damping(self) -> NDArray[np.float64]:
        """(5, 5) damping A_w^T C_w of the wheelset's equations of motion on (y, rx, rz, x, ry)
        (rail at rest)."""
        return self.A_w.T @ self.C_w


@dataclass(frozen=True)
class RollTerms:
    """The rolling-radius terms of one wheel's vertical contact row (module docstring: the roll).

    The row's wheel part z + s l rx becomes z + s l rx + ``wheel_y`` y + ``wheel_rx`` rx, its rail part
    (rail height at the wheel) gains ``rail_y`` y_r (the alignment and the bridge's lateral shape at
    rail level); its force N acts with the same map.

    Attributes
    ----------
    wheel_y, wheel_rx : coefficients on the wheelset's y and rx: -s kappa, -s kappa r0
    rail_y : coefficient on the rail's lateral displacement y_r in the rail part: -s kappa
    """

    wheel_y: float
    wheel_rx: float
    rail_y: float


def rolling_roll_terms(contact: WheelsetContact, side: float, lever: float) -> RollTerms:
    """The rolling-radius terms of the vertical contact row of the wheel on ``side`` (+1 left, -1
    right) at the lever ``lever`` [m] (the row z + side lever rx): kappa = lambda lever / b0, so that
    stiff contacts at +-lever hold the wheelset at the roll lambda e / b0 against the rail plane
    (e = y + r0 rx - y_r). Signs: the gap (rail minus wheel) of the left wheel is
    z_rail - (z + l rx - kappa e): its wheel part z + l rx - kappa (y + r0 rx), its rail part
    z_rail - kappa y_r."""
    if side not in (1.0, -1.0):
        raise SettingError("rolling_roll_terms", "side", side, "+1 (left) or -1 (right)")
    kappa = contact.conicity * lever / contact.half_contact_distance
    s = float(side)
    return RollTerms(wheel_y=-s * kappa, wheel_rx=-s * kappa * contact.rolling_radius, rail_y=-s * kappa)


def creep_rows(contact: WheelsetContact, speed: float) -> CreepRows:
    """The linear creep rows of a wheelset at speed v > 0 [m/s] (formulas in the module docstring)."""
    if not (math.isfinite(speed) and speed > 0):
        raise SettingError("creep_rows", "speed", speed, "a finite speed > 0 m/s (creep damping ~ 1/v)")
    f = contact.coefficients
    r0, b0, lam, W = contact.rolling_radius, contact.half_contact_distance, contact.conicity, contact.axle_load
    v = float(speed)
    kgy, kgp = contact.gravitational_stiffness, contact.gravitational_yaw_stiffness
    f23, f33 = (f.f23, f.f33) if contact.spin else (0.0, 0.0)
    n, nw = len(ROWS), len(WHEEL_COORDINATES)
    K_w, C_w = np.zeros((n, nw)), np.zeros((n, nw))
    K_r, C_r = np.zeros((n, 3)), np.zeros((n, 3))
    # force_y = -2 f22 xi_y - 2 f23 phi - K_gy e - W theta_r
    #   xi_y = (y' + r0 rx' - y_r')/v - rz,  phi = (rz' - psi_r')/v,  e = y + r0 rx - y_r
    K_w[0, :3] = (kgy, kgy * r0, -2.0 * f.f22)
    C_w[0, :3] = (2.0 * f.f22 / v, 2.0 * f.f22 * r0 / v, 2.0 * f23 / v)
    K_r[0] = (kgy, -W, 0.0)
    C_r[0] = (2.0 * f.f22 / v, 0.0, 2.0 * f23 / v)
    # left.force_x = -f11 xi_x,left = -f11 (x' - r0 ry')/v + f11 [lambda e / r0 + b0 (rz' - psi_r')/v];
    # right: the same common part, the opposite antisymmetric part
    for i, s in ((1, 1.0), (2, -1.0)):
        K_w[i, :3] = (-s * f.f11 * lam / r0, -s * f.f11 * lam, 0.0)
        C_w[i] = (0.0, 0.0, -s * f.f11 * b0 / v, f.f11 / v, -f.f11 * r0 / v)
        K_r[i] = (-s * f.f11 * lam / r0, 0.0, 0.0)
        C_r[i] = (0.0, 0.0, -s * f.f11 * b0 / v)
    # moment_z = 2 f23 xi_y - 2 f33 phi - K_gpsi (rz - psi_r)
    K_w[3, :3] = (0.0, 0.0, kgp + 2.0 * f23)
    C_w[3, :3] = (-2.0 * f23 / v, -2.0 * f23 * r0 / v, 2.0 * f33 / v)
    K_r[3] = (0.0, 0.0, kgp)
    C_r[3] = (-2.0 * f23 / v, 0.0, 2.0 * f33 / v)
    # application (virtual work): force_y at y + r0 rx; F_x at x - r0 ry -/+ b0 rz; moment_z on rz
    A_w = np.array([[1.0, r0, 0.0, 0.0, 0.0], [0.0, 0.0, -b0, 1.0, -r0], [0.0, 0.0, b0, 1.0, -r0],
                    [0.0, 0.0, 1.0, 0.0, 0.0]])
    A_r = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -b0], [0.0, 0.0, b0], [0.0, 0.0, 1.0]])
    return CreepRows(rows=ROWS, K_w=K_w, C_w=C_w, A_w=A_w, K_r=K_r, C_r=C_r, A_r=A_r, speed=v)
