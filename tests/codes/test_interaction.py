"""A real train with vehicle-bridge interaction against the same train as moving forces (issue 48,
"Interaction"): tb_exudyn.codes.interaction.

The problem: the ICE of the reference study (ice_mttm: motor car, two trailers, motor car, all 24.775 m
long) crosses one 15 m simply supported span (E I / m chosen for a first bending frequency n0 = 6 Hz by
the closed form, m = 15 t/m, damping 1.35 % = Table 6.6's lower limit for prestressed concrete at 15 m,
track on the girder's axis) at the second resonance speed of its regular spacing D = 24.775 m:
v = n0 D / 2 = 267.6 km/h (EN 1991-2 eq. 6.9's v_i = n0 lambda_i with lambda = D / i).

- The moving-force part against an independent solver written here: the closed-form modes of the
  Euler-Bernoulli beam (sin(n pi x / L), n = 1 ... 3: every vertical mode under 60 Hz), each modal equation
  integrated by scipy's DOP853 at rtol 1e-10 and sampled every 0.1 ms (1667 samples per period of the first
  mode, which makes the peak: the sampled peak within 1 - cos(pi / 1667) = 2e-6 of the true one). Measured
  2.3e-6 apart; tolerance 2e-4: the FE model's first frequency is within 1e-6 of the closed form and its
  third (a small part of the peak) within 1e-4, the solver's peak within 3e-5 at its 80 samples per period
  (interaction.MF_SAMPLES_PER_PERIOD) and its parabola refinement within 1e-5; far below the effect (14 %).
- The train's axle loads (what the moving forces carry) are the vehicles' weights per axle: the same load on
  the bridge in both models.
- Interaction lowers the mid-span peak, and the interaction run reached its end time.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.codes import en1991
from tb_exudyn.codes.interaction import interaction_comparison
from tb_exudyn.codes.trains import resolve_trains
from tb_exudyn.scenario.model import SimpleBeam
from tb_exudyn.scenario.sections import BeamSection

pytestmark = pytest.mark.exudyn

L, M, E, N0, G = 15.0, 15000.0, 3.45e10, 6.0, 9.81
#: E I of a first bending frequency N0: f1 = (pi / (2 L^2)) sqrt(E I / m)
EI = (2.0 * L * L * N0 / math.pi) ** 2 * M
ZETA = en1991.damping_ratio_table_6_6("prestressed_concrete", L)


def span_15m() -> SimpleBeam:
    section = BeamSection(E=E, G=E / 2.4, area=6.0, I_y=EI / E, I_z=5.0, J=3.0, mass_per_length=M,
                          rot_mass_per_length=5.0e4)
    return SimpleBeam(name="span_15m", spans=(L,), girder=section, damping_ratio=ZETA, elements_per_span=16,
                      track_offset=0.0)


def closed_form_mid_span_peak(positions: np.ndarray, loads: np.ndarray, v: float, zeta: float,
                              tail_s: float) -> float:
    """Peak |acceleration| at mid-span of the closed-form beam under the moving loads (modes n = 1..3)."""
    from scipy.integrate import solve_ivp

    n = np.arange(1, 4)
    w = (n * math.pi / L) ** 2 * math.sqrt(EI / M)
    scale = 2.0 / (M * L)  # 1 / modal mass of sin(n pi x / L)

    def load(t: float) -> np.ndarray:
        x = v * t - positions
        on = (x >= 0.0) & (x <= L)
        return -scale * (loads[on, None] * np.sin(np.outer(x[on], n) * math.pi / L)).sum(axis=0)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, p = y[:3], y[3:]
        return np.concatenate([p, load(t) - 2.0 * zeta * w * p - w * w * q])

    end = (L + positions.max()) / v + tail_s
    t = np.arange(0.0, end, 1e-4)
    sol = solve_ivp(rhs, (0.0, end), np.zeros(6), method="DOP853", rtol=1e-10, atol=1e-14, t_eval=t,
                    max_step=1e-3)
    acc = np.array([rhs(ti, yi)[3:] for ti, yi in zip(sol.t, sol.y.T)])
    return float(np.abs(acc @ np.sin(n * math.pi / 2.0)).max())


def test_interaction_lowers_the_resonant_peak_of_a_15m_span():
    train = resolve_trains(["ice_mttm"])[0]
    spacing = train.vehicles[0].geometry.length
    assert all(abs(c.geometry.length - spacing) < 1e-12 for c in train.vehicles)
    weight = G * sum(c.body.mass + 2 * c.bogie.mass + 4 * c.wheelset.mass for c in train.vehicles)
    assert np.isclose(np.sum(train.loads), weight, rtol=1e-9)

    v_kmh = 3.6 * N0 * spacing / 2.0
    cmp = interaction_comparison(span_15m(), train, v_kmh, max_frequency=60.0)

    assert cmp.frequencies[0] == pytest.approx(N0, rel=1e-5)
    tail_s = 2.0 / cmp.frequencies.min()  # the moving-force solver's free vibration after the last axle
    ref = closed_form_mid_span_peak(np.asarray(train.positions), np.asarray(train.loads), v_kmh / 3.6, ZETA, tail_s)
    assert cmp.moving_force_acc[0] == pytest.approx(ref, rel=2e-4)

    assert cmp.end_time_s == pytest.approx(cmp.planned_end_time_s, abs=1.5e-3)
    assert cmp.max_interaction < cmp.max_moving_force
    assert cmp.reduction > 0.0
    # eq. 6.13 at 15 m: its Delta zeta lowers the moving-force peak too
    assert cmp.additional_damping == pytest.approx(en1991.additional_damping_eq_6_13(L))
    assert cmp.max_moving_force_dz < cmp.max_moving_force
    print(f"\n15 m span, n0 = {N0} Hz, zeta = {100 * ZETA:.3g} %, v = {v_kmh:.4g} km/h: moving forces "
          f"{cmp.max_moving_force:.4g} m/s^2 (closed form {ref:.4g}, {cmp.moving_force_acc[0] / ref - 1:+.2e}), zeta + Delta zeta "
          f"({100 * cmp.additional_damping:.3g} %) {cmp.max_moving_force_dz:.4g} m/s^2 (-{100 * cmp.reduction_dz:.3g} %), "
          f"interaction {cmp.max_interaction:.4g} m/s^2 (-{100 * cmp.reduction:.3g} %), {cmp.seconds:.3g} s")


def test_a_train_of_axle_loads_only_is_refused():
    from tb_exudyn.errors import SettingError

    hslm = resolve_trains(["HSLM-A1"])[0]
    with pytest.raises(SettingError, match="vehicle models"):
        interaction_comparison(span_15m(), hslm, 250.0)


def test_the_check_reports_interaction_beside_moving_forces_per_real_train():
    """check(..., interaction=True): one comparison per train of vehicle models, at the speed of its largest
    mid-span peak among the check's rows, whose moving-force peak is that row's (the same solver on the same
    modes), at the check's damping without Delta zeta. Tolerance 1e-3: the check integrates all speeds with
    the step of its lowest (20 samples per period there), the comparison its one speed at 80 samples per
    period; the solver's peak converges as dx^2 (MF_SAMPLES_PER_PERIOD's note: 6e-4 at 20 samples at 283
    km/h, so about 2e-4 at the check's finer step)."""
    from tb_exudyn.codes.check import check

    res = check(span_15m(), 250.0, trains=["ice_mttm", "HSLM-A1"], construction="prestressed_concrete",
                cases=["nominal"], interaction=True)
    (cmp,) = res.interaction
    rows = [r for r in res.rows if r["train"] == "ice_mttm"]
    top = max(rows, key=lambda r: r["acc_z_mid_span1"])
    assert cmp.train == "ice_mttm" and cmp.case == "nominal" and cmp.speed_kmh == top["speed_kmh"]
    assert cmp.damping_ratio == pytest.approx(ZETA)
    assert cmp.max_moving_force == pytest.approx(top["acc_z_mid_span1"], rel=1e-3)
    assert cmp.end_time_s == pytest.approx(cmp.planned_end_time_s, abs=1.5e-3)
    assert cmp.difference < 0.0 and cmp.difference == pytest.approx(cmp.max_interaction - cmp.max_moving_force)
    assert "interaction" in res.summary() and f"{cmp.max_interaction:.3f}" in res.summary()
    print(f"\ncheck row: {cmp.train} at {cmp.speed_kmh:.1f} km/h: moving forces {cmp.max_moving_force:.4g}, "
          f"interaction {cmp.max_interaction:.4g} ({-100 * cmp.reduction:+.3g} %), zeta + Delta zeta "
          f"{cmp.max_moving_force_dz:.4g} m/s^2; check {res.seconds:.3g} s")


@pytest.mark.parametrize("asked, trains", [("yes", ["ice_mttm"]), (True, ["HSLM-A1"])])
def test_the_check_refuses_interaction_without_a_train_of_vehicles(asked, trains):
    from tb_exudyn.codes.check import check
    from tb_exudyn.errors import SettingError

    with pytest.raises(SettingError, match="interaction"):
        check(span_15m(), 250.0, trains=trains, construction="prestressed_concrete", cases=["nominal"],
              interaction=asked)


def test_the_command_refuses_interaction_without_a_train_of_vehicles_before_any_work(tmp_path, capsys):
    """`tb-exudyn check ... --interaction` with HSLM-A only: exit 2, one line naming --interaction, --out untouched."""
    from tb_exudyn.cli import main

    out = tmp_path / "chk"
    assert main(["check", "single_span_32m", "--line-speed-kmh", "200", "--trains", "HSLM-A1", "--interaction",
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--interaction" in err[0] and "vehicle models" in err[0]
    assert not out.exists()


def test_the_command_reports_interaction_on_the_terminal_and_the_page(tmp_path, capsys):
    """`tb-exudyn check BRIDGE.toml --trains ice_mttm --interaction`: the terminal's interaction line and the
    page's Interaction section carry the same numbers as CheckResult.interaction of the library call."""
    from tb_exudyn.cli import main
    from tb_exudyn.scenario.io import load_bridge

    b, g = span_15m(), span_15m().girder
    path = tmp_path / "span_15m.toml"
    path.write_text(f'kind = "simple_beam"\nname = "span_15m"\nspans = [{L!r}]\ndamping_ratio = {ZETA!r}\n'
                    f'track_offset = 0.0\nelements_per_span = 16\n\n[girder]\n'
                    + "".join(f"{k} = {getattr(g, k)!r}\n" for k in ("E", "G", "area", "I_y", "I_z", "J",
                                                                      "mass_per_length", "rot_mass_per_length")),
                    encoding="utf-8")
    assert load_bridge(path) == b
    out = tmp_path / "chk"
    assert main(["check", str(path), "--line-speed-kmh", "250", "--trains", "ice_mttm", "--construction",
                 "prestressed_concrete", "--interaction", "--no-figures", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    line = next(x for x in text.splitlines() if x.strip().startswith("ice_mttm") and "%" in x)
    page = (out / "check.html").read_text(encoding="utf-8")
    assert 'id="interaction"' in page
    moving, inter = (float(w) for w in line.split()[3:5])
    assert inter < moving and f"{inter:.3f}" in page and f"{moving:.3f}" in page
