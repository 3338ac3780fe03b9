"""The continuous girder (bridge kind ``continuous``) against closed forms.

1. Natural frequencies of a girder continuous over two and over three equal spans L on rigid point
   supports (pinned at the shear centre, every bearing rigid, no bearing height), Euler-Bernoulli
   (shear_area_factor 0; the element has no rotary inertia of bending either, so the FE model
   discretises exactly the Euler-Bernoulli beam), against the roots of the continuous-beam
   frequency equations typed below.

   Derivation (slope-deflection with the dynamic stiffness functions of a span, Kolousek's method):
   a span of length L vibrating at omega with zero deflection at both ends and end rotations
   theta_a, theta_b has the end moments (EI / L) (a theta_a + b theta_b) and (EI / L) (b theta_a +
   a theta_b), with lambda = beta L, beta^4 = m omega^2 / (EI),

       a(lambda) = lambda (sinh l cos l - cosh l sin l) / (cos l cosh l - 1)
       b(lambda) = lambda (sin l - sinh l) / (cos l cosh l - 1)

   (static limit a = 4, b = 2: the static slope-deflection factors, checked below). Moment
   equilibrium at every support (zero moment at the two end supports) of n equal spans gives a
   tridiagonal system in the support rotations with diagonal (a, 2a, ..., 2a, a) and b beside it.
   Its determinant factorises by the symmetry about the middle:

   - two spans: 2 a (a - b)(a + b) = 0; (a - b)(a + b) = 0 is sin(lambda) = 0 (each span a
     simply supported span, antisymmetric modes), a = 0 is tan(lambda) = tanh(lambda) (each span
     clamped at the middle support, symmetric modes);
   - three spans: (a - b)(a + b)(2a + b)(2a - b) = 0: sin(lambda) = 0, or
     2 (sinh l cos l - cosh l sin l) +- (sin l - sinh l) = 0.

   Frequencies f = lambda^2 / (2 pi L^2) sqrt(EI / m). Tolerance 0.1 % (issue 29's acceptance) on
   each of the first six vertical modes; 16 cubic elements per span are inside it (the error of the
   consistent-mass Hermite element falls as h^4: 1e-6 for the first mode, 1.1e-4 for the sixth of
   two spans, lambda = 10.2, measured).

2. A static deflection against the three-moment equation (Clapeyron), with a different span length
   and section in each span (``girders``, sections per span): support moments from

       M_{i-1} L_i / I_i + 2 M_i (L_i / I_i + L_{i+1} / I_{i+1}) + M_{i+1} L_{i+1} / I_{i+1}
           = - P a (L_i^2 - a^2) / (L_i I_i)     (a load P in span i, a from its left support)
             - P b (L_{i+1}^2 - b^2) / (L_{i+1} I_{i+1})   (in span i + 1, b from its right support)

   (M_0 = M_n = 0, E the same everywhere), then the deflection of each span as a simply supported
   span under its load and its end moments. The FE solution of cubic elements is exact at the
   nodes for nodal loads (the Hermite cubics solve the static beam equation), so the tolerance is
   round-off: 1e-8 relative.

3. A pier under a continuous girder: two equal spans, the middle support a pier (axial stiffness
   E_p A_p / H) and a load P straight over it: the girder is a beam of 2 L on the abutments with
   the pier as a spring at mid-length, delta = P / (E_p A_p / H + 48 E I / (2 L)^3); exact for the
   FE model as in 2 (round-off tolerance).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from tb_exudyn.scenario import ScenarioError
from tb_exudyn.scenario.io import load_bridge
from tb_exudyn.scenario.model import BeamSection, Continuous, ContinuousBearings, Pier
from tb_exudyn.structure import StructureError, assemble, bridge_modes, modal_bridge
from tb_exudyn.structure.fe import static_displacement

E, I_Y, MASS = 3.45e10, 10.947, 22222.25  # the li_zhu girder (models/bridges/li_zhu_2011_bridge.toml)
SPAN = 32.0


def section(i_y: float = I_Y) -> BeamSection:
    # lateral bending and torsion much stiffer: the first vertical modes come first (they are
    # uncoupled from them anyway: the mass lies on the shear centre)
    return BeamSection(E=E, G=1.4375e10, area=8.8889, I_y=i_y, I_z=50 * I_Y, J=50 * I_Y, mass_per_length=MASS,
                       rot_mass_per_length=1e3)


def rigid_continuous(spans, **kw) -> Continuous:
    kw.setdefault("girder", section())
    kw.setdefault("elements_per_span", 16)
    return Continuous(name="cont", spans=tuple(spans), supports=("rigid",) * (len(spans) - 1), **kw)


# --------------------------------------------------------------------------------------------
# the frequency equations


def kolousek_a(l: float) -> float:
    return l * (math.sinh(l) * math.cos(l) - math.cosh(l) * math.sin(l)) / (math.cos(l) * math.cosh(l) - 1.0)


def kolousek_b(l: float) -> float:
    return l * (math.sin(l) - math.sinh(l)) / (math.cos(l) * math.cosh(l) - 1.0)


def two_span_symmetric(l: float) -> float:
    """a = 0: tan(l) = tanh(l), written without poles."""
    return math.sinh(l) * math.cos(l) - math.cosh(l) * math.sin(l)


def three_span_plus(l: float) -> float:
    """2 a + b = 0 (numerator)."""
    return 2.0 * (math.sinh(l) * math.cos(l) - math.cosh(l) * math.sin(l)) + (math.sin(l) - math.sinh(l))


def three_span_minus(l: float) -> float:
    """2 a - b = 0 (numerator)."""
    return 2.0 * (math.sinh(l) * math.cos(l) - math.cosh(l) * math.sin(l)) - (math.sin(l) - math.sinh(l))


def roots(fun, upper: float, step: float = 0.01) -> list[float]:
    """Every sign change of ``fun`` on (0.5, upper), refined by brentq (the equations scale like
    e^l, so they are divided by cosh(l) first)."""
    g = lambda l: fun(l) / math.cosh(l)
    grid = np.arange(0.5, upper, step)
    vals = [g(x) for x in grid]
    return [brentq(g, grid[i], grid[i + 1], xtol=1e-14) for i in range(len(grid) - 1) if vals[i] * vals[i + 1] < 0]


def closed_form_lambdas(n_spans: int, count: int = 6) -> list[float]:
    upper = 12.0
    lams = [k * math.pi for k in range(1, 4)]  # sin(l) = 0
    if n_spans == 2:
        lams += roots(two_span_symmetric, upper)
    else:
        lams += roots(three_span_plus, upper) + roots(three_span_minus, upper)
    return sorted(lams)[:count]


def test_kolousek_functions_have_the_static_limit():
    """a -> 4, b -> 2 as lambda -> 0 (slope-deflection 4 EI / L and 2 EI / L): the typed functions are
    the span's rotational stiffness. Tolerance: their lambda^4 term (about 3e-9 at 0.01) and round-off
    of the 1 - cos cosh difference (about 1e-16 / 1e-4 relative at lambda = 0.01)."""
    assert kolousek_a(0.01) == pytest.approx(4.0, rel=1e-6)
    assert kolousek_b(0.01) == pytest.approx(2.0, rel=1e-6)


def test_closed_form_roots_are_the_factored_equations():
    """The first roots of the factored equations are roots of the unfactored determinant of the
    support-moment equations (a check of the factorisation typed above), to round-off."""
    for n, lams in ((2, closed_form_lambdas(2)), (3, closed_form_lambdas(3))):
        for lam in lams:
            a, b = kolousek_a(lam + 1e-9), kolousek_b(lam + 1e-9)  # off sin(l) = 0 exactly: no 0 / 0
            k = np.diag([a] + [2 * a] * (n - 1) + [a]) + np.diag([b] * n, 1) + np.diag([b] * n, -1)
            sv = np.linalg.svd(k, compute_uv=False)
            assert sv[-1] / sv[0] < 1e-6, (n, lam)  # singular (the 1e-9 offset leaves about 1e-8)


@pytest.mark.parametrize("n_spans", [2, 3])
def test_equal_span_frequencies_match_the_continuous_beam_equations(n_spans):
    lams = closed_form_lambdas(n_spans)
    expected = np.array([lam**2 / (2 * math.pi * SPAN**2) * math.sqrt(E * I_Y / MASS) for lam in lams])
    modes = bridge_modes(rigid_continuous([SPAN] * n_spans), max_frequency=1.2 * expected[-1])
    vertical = np.array([f for f, t in zip(modes.frequencies, modes.mode_types) if t == "vertical"])
    assert vertical.size >= 6
    np.testing.assert_allclose(vertical[:6], expected, rtol=1e-3)
    # the first mode of n equal continuous spans is the simply supported span's (lambda = pi)
    assert vertical[0] == pytest.approx(math.pi**2 / (2 * math.pi * SPAN**2) * math.sqrt(E * I_Y / MASS), rel=1e-4)


# --------------------------------------------------------------------------------------------
# static deflections


def three_moment(spans, inertias, loads) -> np.ndarray:
    """Support moments M_0 ... M_n (sagging positive) of a continuous beam on rigid supports under
    point loads ``loads`` = [(span index, a from its left support, P downward)]."""
    n = len(spans)
    mat = np.zeros((n - 1, n - 1))
    rhs = np.zeros(n - 1)
    for i in range(1, n):  # the equation at support i, between span i - 1 and span i (0-based spans)
        li, ii, lj, ij = spans[i - 1], inertias[i - 1], spans[i], inertias[i]
        if i - 2 >= 0:
            mat[i - 1, i - 2] = li / ii
        mat[i - 1, i - 1] = 2 * (li / ii + lj / ij)
        if i < n - 1:
            mat[i - 1, i] = lj / ij
        for s, a, p in loads:
            if s == i - 1:
                rhs[i - 1] -= p * a * (li**2 - a**2) / (li * ii)
            elif s == i:
                b = lj - a
                rhs[i - 1] -= p * b * (lj**2 - b**2) / (lj * ij)
    return np.concatenate([[0.0], np.linalg.solve(mat, rhs), [0.0]])


def span_deflection(x, length, ei, m_a, m_b, loads_in_span) -> float:
    """Downward deflection at x of a simply supported span under its point loads [(a, P)] and the end
    moments m_a, m_b (sagging positive)."""
    v = (m_a * x * (length - x) * (2 * length - x) + m_b * x * (length - x) * (length + x)) / (6 * ei * length)
    for a, p in loads_in_span:
        b = length - a
        if x <= a:
            v += p * b * x * (length**2 - b**2 - x**2) / (6 * ei * length)
        else:
            xr = length - x
            v += p * a * xr * (length**2 - a**2 - xr**2) / (6 * ei * length)
    return v


def girder_node(model, x: float) -> int:
    girder = np.flatnonzero((model.node_part == 0) & np.isclose(model.coordinates[:, 0], x, atol=1e-9))
    assert girder.size == 1, f"one girder node at x = {x}"
    return int(girder[0])


def test_static_deflection_matches_the_three_moment_equation_with_a_section_per_span():
    spans = (24.0, 32.0, 28.0)
    inertias = (8.0, 10.947, 9.5)
    bridge = rigid_continuous(spans, girder=None, girders=tuple(section(i) for i in inertias))
    model = assemble(bridge)
    # loads at nodes (2 m, 1.75 m and 1.5 m element lengths): 150 kN at 12 m into span 2, 80 kN at 7 m into span 3
    loads = [(1, 12.0, 1.5e5), (2, 7.0, 8.0e4)]
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    f = np.zeros(model.n_dof)
    for s, a, p in loads:
        f[model.dof(girder_node(model, starts[s] + a), "uz")] = -p
    u = static_displacement(model, f)
    moments = three_moment(spans, inertias, loads)
    for s, x in ((1, 12.0), (2, 7.0), (0, 12.0), (2, 21.0)):  # the load points and points of the other spans
        expected = span_deflection(x, spans[s], E * inertias[s], moments[s], moments[s + 1],
                                   [(a, p) for t, a, p in loads if t == s])
        got = -u[model.dof(girder_node(model, starts[s] + x), "uz")]
        assert got == pytest.approx(expected, rel=1e-8), (s, x)
    # the unloaded first span lifts (the hogging moment over the first support)
    assert moments[1] < 0 and -u[model.dof(girder_node(model, 12.0), "uz")] < 0


def test_a_pier_support_acts_as_its_axial_spring():
    pier_section = BeamSection(E=3.25e10, G=1.3542e10, area=19.069, I_y=12.976, I_z=66.25, J=41.0,
                               mass_per_length=47672.5, rot_mass_per_length=198065.0)
    height = 15.0
    bridge = Continuous(name="on_pier", spans=(SPAN, SPAN), girder=section(), supports=("pier",),
                        pier=Pier(height=height, section=pier_section),
                        bearings=ContinuousBearings(height=2.3, fixed_support=1), elements_per_span=8)
    model = assemble(bridge)
    node = girder_node(model, SPAN)
    f = np.zeros(model.n_dof)
    p = 1.0e6
    f[model.dof(node, "uz")] = -p
    u = static_displacement(model, f)
    k_pier = pier_section.E * pier_section.area / height
    k_beam = 48 * E * I_Y / (2 * SPAN) ** 3
    assert -u[model.dof(node, "uz")] == pytest.approx(p / (k_pier + k_beam), rel=1e-8)
    assert model.pier_top_nodes and len(model.pier_top_nodes) == 1


# --------------------------------------------------------------------------------------------
# the shipped example and the data rules


def test_shipped_continuous_bridge_gives_modes_and_stations():
    """models/bridges/continuous_3x32m.toml: its modal model has the stations of three spans and two
    pier tops. On rigid supports with the bearings at the shear centre, its first vertical mode is
    lambda = pi of three equal continuous spans: the simply supported span's (pi / L)^2 sqrt(EI / m) /
    (2 pi) with the girder's and the added mass (3.39e4 kg/m, 5.120 Hz), to the FE error (1e-4: the
    first mode's discretisation error is about 1e-7). On its piers with the bearings 2.3 m below the
    axis it moves by +0.12 % (the fixed bearing below the axis is held by the girder's longitudinal
    inertia above the 1.4 Hz longitudinal mode): within 2 %."""
    bridge = load_bridge("continuous_3x32m")
    assert isinstance(bridge, Continuous)
    mb = modal_bridge(bridge, 30.0)
    assert mb.station_names[:3] == ("span1.q1", "span1.mid", "span1.q3")
    assert "pier2.top" in mb.station_names and "span3.mid" in mb.station_names
    f_ss = math.pi / (2 * SPAN**2) * math.sqrt(E * I_Y / (MASS + 11677.75))
    rigid = bridge.replace(supports=("rigid", "rigid"), bearings=bridge.bearings.replace(height=0.0))
    for b, rtol in ((rigid, 1e-4), (bridge, 2e-2)):
        m = bridge_modes(b, 30.0)
        f1 = next(f for f, t in zip(m.frequencies, m.mode_types) if t == "vertical")
        assert f1 == pytest.approx(f_ss, rel=rtol)


def test_a_continuous_girder_needs_a_support_per_span_joint():
    with pytest.raises(ScenarioError) as exc:
        Continuous(name="c", spans=(32.0, 32.0), girder=section(), supports=())
    assert exc.value.key == "supports" and "without supports" in str(exc.value)
    with pytest.raises(ScenarioError) as exc:
        Continuous(name="c", spans=(32.0, 32.0, 32.0), girder=section(), supports=("rigid",))
    assert exc.value.key == "supports" and "2 entries" in str(exc.value)
    with pytest.raises(ScenarioError) as exc:
        Continuous(name="c", spans=(32.0, 32.0), girders=(section(),), supports=("rigid",))
    assert exc.value.key == "girders"
    with pytest.raises(ScenarioError) as exc:
        Continuous(name="c", spans=(32.0, 32.0), girder=section(), supports=("pier",))
    assert exc.value.key == "pier"


def test_free_bearings_name_the_bearing_key():
    """Every bearing free vertically: a mechanism named by bearings.k_z (no traceback, one key)."""
    bridge = rigid_continuous([SPAN, SPAN], bearings=ContinuousBearings(k_z=0.0))
    with pytest.raises(StructureError) as exc:
        bridge_modes(bridge, 60.0)
    assert exc.value.key == "bearings.k_z"


@pytest.mark.parametrize("supports", [("pier", "pier"), ("rigid", "pier")])
def test_size_estimate_counts_the_dofs_exactly_and_the_modes_from_above(supports):
    """structure/size.py before assembly: the DOFs of continuous_3x32m (one girder node per span joint,
    a pier per support 'pier') equal the assembled model's; the mode count from its parts (each span
    a simple span, each pier alone, times FRAME_MARGIN) is no fewer than the solved count below 100 Hz
    (55 and 49 modes; estimates 75 and 65)."""
    from tb_exudyn.structure.fe import solve_modes
    from tb_exudyn.structure.size import bridge_size, estimate_modes

    bridge = load_bridge("continuous_3x32m").replace(supports=supports)
    model = assemble(bridge)
    assert bridge_size(bridge, 100.0, 0, solve_modes).n_dof == model.n_dof
    assert estimate_modes(bridge, 100.0, 0, solve_modes) >= solve_modes(model, 100.0).n_modes


def test_show_describes_a_continuous_bridge(capsys):
    """tb-exudyn show with the continuous bridge: its keys (supports, fixed_support) and the FE
    frequencies of the bridge alone (the first vertical mode as in the test above, 5.126 Hz)."""
    from tb_exudyn.cli import main

    assert main(["show", "quick", "--set", "bridge=continuous_3x32m"]) == 0
    out = capsys.readouterr().out
    assert "bridge.kind" in out and "continuous" in out
    assert "bridge.supports" in out and "[pier, pier]" in out
    assert "bridge.bearings.fixed_support" in out
    row = next(line for line in out.splitlines() if line.startswith("(derived) bridge f1, f3 vertical"))
    assert "5.126" in row


@pytest.mark.parametrize("per_span", [False, True])
def test_a_scenario_with_a_continuous_bridge_round_trips(per_span, tmp_path):
    """save_scenario writes the continuous bridge inline (result files keep it so); loading it gives
    an equal scenario, with one girder section or one per span ([[girders]])."""
    from tb_exudyn.scenario import load_scenario, save_scenario
    from tb_exudyn.scenario.io import with_settings

    sc = with_settings(load_scenario("quick"), [("bridge", "continuous_3x32m")])
    if per_span:
        g = sc.bridge.girder
        sc = sc.replace(bridge=sc.bridge.replace(girder=None, girders=(g, g.replace(I_y=12.0), g)))
    again = load_scenario(save_scenario(sc, tmp_path / "sc.toml"))
    assert again == sc and isinstance(again.bridge, Continuous)
    assert len(again.bridge.sections) == 3 and (again.bridge.sections[1].I_y == 12.0) == per_span


def test_the_en1991_check_takes_a_continuous_girder():
    """codes/check.py with a Continuous object (not only a file name): continuous_3x32m under HSLM-A1
    at a 250 km/h line speed, nominal mass case. Its mode list is the FE model's at the check's mesh
    (64 elements per span; the first vertical mode 5.126 Hz as above, to 1e-3), one mid-span column per
    span, and every row's deck acceleration a finite number > 0 (the moving-force response ran)."""
    from tb_exudyn.codes.check import check

    result = check(load_bridge("continuous_3x32m"), 250.0, trains=["HSLM-A1"], cases=["nominal"])
    assert result.vertical_frequencies[0] == pytest.approx(5.126, rel=1e-3)
    assert {f"acc_z_mid_span{i}" for i in (1, 2, 3)} <= set(result.columns)
    accs = [row["max_deck_acc_z"] for row in result.rows]
    assert accs and all(math.isfinite(a) and a > 0 for a in accs)
