"""Derived channel definitions (tb_exudyn.system.derived) against closed forms typed here.

Problem: two simply supported spans (24 m and 31.3 m: no common torsion frequency) with closed-form bending and torsion modes
(tb_exudyn.structure.simply_supported_modes), the track 2 m off the girder axis, rails at +-0.7175 m.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.errors import ScenarioError
from tb_exudyn.structure import simply_supported_modes
from tb_exudyn.system.channels import catalogue
from tb_exudyn.system.derived import (
    derivative_name,
    derived_catalogue,
    en1990_cut_frequency,
    engine_outputs,
    extended_shapes,
    select_channels,
    station_positions,
)

SPANS = (24.0, 31.3)
B = 0.7175
EI_V, EI_L, GJ, MU, IP = 2.0e11, 8.0e11, 5.0e10, 2.0e4, 2.0e5


@pytest.fixture(scope="module")
def setup():
    bridge = simply_supported_modes(SPANS, EI_V, EI_L, GJ, MU, IP, 0.02, 80.0, track_offset=2.0, track_height=1.0)
    bodies = [("car1.body", 10, (("y", 1), ("z", 2))), ("car1.axle1", 11, (("y", 1), ("z", 2), ("rx", 3)))]
    contacts = ["car1.axle1.left.force_z", "car1.axle1.right.force_z", "car1.axle1.force_y"]
    channels = catalogue(bridge.station_names, bodies, contacts, [])
    stations = station_positions(bridge.station_names, SPANS)
    cat = derived_catalogue(channels, stations, bridge, B, record_length=3.0)
    return bridge, channels, stations, cat


def _effective_row(cat, bridge, name: str) -> np.ndarray:
    """The z shape row over the modes that a linear derived channel of bridge rows amounts to."""
    d = next(c for c in cat.channels if c.name == name)
    aux = {c.name: c for c in cat.auxiliary}
    shapes = extended_shapes(bridge.station_shapes, cat)
    return sum(coef * shapes[aux[n].index, aux[n].coordinate] for n, coef in d.terms)


def test_twist_is_the_rail_height_difference_over_3_m(setup):
    """Reference: z_L - z_R = 2 b theta on the track line, theta_j(x) = sqrt(2 / (I_p L)) sin(j pi xi / L)
    for the torsion modes of the span holding x (xi from its start; zero for bending modes and off
    the span), so twist_j = 2 b [theta_j(x + 1.5) - theta_j(x - 1.5)] (typed here from the closed
    form). The vertical modes and the track offset's e theta cancel between the rails. 1e-12 relative."""
    bridge, _, stations, cat = setup
    starts = np.concatenate(([0.0], np.cumsum(SPANS)[:-1]))
    kinds = bridge.mode_types
    f = bridge.frequencies
    # recover j and the span of each torsion mode from its frequency: f = (j pi / L) sqrt(GJ / Ip) / 2 pi
    names = [n for n in stations if not n.startswith("pier")]
    assert {"span1.start", "span1.end", "span2.mid", "span2.q3"} <= set(names)
    for st in names:
        x = stations[st]
        row = _effective_row(cat, bridge, f"bridge.{st}.twist_3m")
        ref = np.zeros(f.size)
        for k, kind in enumerate(kinds):
            if kind != "torsion":
                continue
            for s, (x0, L) in enumerate(zip(starts, SPANS)):
                j = f[k] * 2 * math.pi / (math.pi / L * math.sqrt(GJ / IP))
                if abs(j - round(j)) < 1e-9 and round(j) >= 1:
                    amp = math.sqrt(2 / (IP * L))

                    def theta(xx, x0=x0, L=L, j=round(j), amp=amp):
                        xi = xx - x0
                        return amp * math.sin(j * math.pi * xi / L) if 0 <= xi <= L else 0.0

                    ref[k] = 2 * B * (theta(x + 1.5) - theta(x - 1.5))
                    break
        assert np.max(np.abs(row - ref)) <= 1e-12 * np.max(np.abs(ref)), st
    assert stations["span1.start"] == 1.5 and stations["span2.end"] == sum(SPANS) - 1.5


def test_en1990_acceleration_keeps_the_modes_up_to_the_code_range(setup):
    """Reference: f_cut = max(30 Hz, 1.5 f1, f3) with the closed-form vertical frequencies
    (j pi / L)^2 sqrt(EI / m) / (2 pi) of both spans (first and third lowest); the channel's shape row
    is the track line's vertical row with every mode above f_cut set to zero (exact)."""
    bridge, _, _, cat = setup
    fv = sorted((j * math.pi / L) ** 2 * math.sqrt(EI_V / MU) / (2 * math.pi) for L in SPANS for j in range(1, 8))
    fv = [x for x in fv if x <= 80.0]
    cut = max(30.0, 1.5 * fv[0], fv[2])
    assert abs(cat.cut_frequency / cut - 1) < 1e-12
    assert abs(en1990_cut_frequency(bridge.frequencies, bridge.mode_types) - cut) < 1e-9
    assert 0 < (bridge.frequencies > cut).sum() < bridge.n_modes  # the test cuts something and keeps something
    row = _effective_row(cat, bridge, "bridge.span2.mid.acc_z_en1990")
    ref = np.where(bridge.frequencies <= cut, bridge.rail_shapes(np.array([SPANS[0] + SPANS[1] / 2])).z[0], 0.0)
    assert np.array_equal(row, ref)


def test_en1990_acceleration_is_along_the_track_torsion_included(setup):
    """Exact problem: the fixture's bridge (track 2 m off the girder axis) at mid-span of span 2.
    Reference, typed from the closed forms: a vertical mode moves the track line by w_j =
    sqrt(2 / (m L)) sin(j pi xi / L), a torsion mode by e theta_j = 2 sqrt(2 / (I_p L)) sin(j pi xi /
    L) (mass-normalised; xi = L / 2 from the span's start: only odd j). The channel's row is w + e
    theta over the modes up to f_cut, larger than the girder axis' row (w alone) by e theta on the
    torsion modes. 1e-12 relative: the closed form evaluated twice."""
    bridge, _, _, cat = setup
    L, xi, e = SPANS[1], SPANS[1] / 2, 2.0
    row = _effective_row(cat, bridge, "bridge.span2.mid.acc_z_en1990")
    ref = np.zeros(bridge.n_modes)
    for k, (f, kind) in enumerate(zip(bridge.frequencies, bridge.mode_types)):
        if f > cat.cut_frequency:
            continue
        if kind == "vertical":
            j = f * 2 * math.pi / ((math.pi / L) ** 2 * math.sqrt(EI_V / MU))
            shape, amp = math.sin, math.sqrt(2 / (MU * L))
        elif kind == "torsion":
            j = f * 2 * math.pi / (math.pi / L * math.sqrt(GJ / IP))
            shape, amp = math.sin, e * math.sqrt(2 / (IP * L))
        else:
            continue
        if abs(j - round(j)) < 1e-9 and round(j) >= 1:  # a mode of span 2 (span 1's have other frequencies)
            ref[k] = amp * shape(round(j) * math.pi * xi / L)
    assert np.max(np.abs(row - ref)) <= 1e-12 * np.max(np.abs(ref))
    s = bridge.station_names.index("span2.mid")
    axis = np.where(bridge.frequencies <= cat.cut_frequency, bridge.station_shapes[s, 1], 0.0)
    torsion = np.array([k == "torsion" for k in bridge.mode_types])
    assert np.abs(row - axis)[torsion].max() > 0.1 * np.abs(ref).max()  # the torsion term is there and not small
    assert np.allclose(row[~torsion], axis[~torsion], rtol=1e-12, atol=1e-15)


def test_names_units_and_what_the_15_dof_model_gives(setup):
    _, channels, _, cat = setup
    by = {c.name: c for c in cat.channels}
    assert by["car1.body.acc_z_wb"].unit == "m/s^2" and by["car1.body.acc_z_wb"].weighting == "wb"
    assert by["car1.body.acc_y_wd"].weighting == "wd"
    assert by["car1.body.sperling_z"].window == 3.0  # the record (3 s) is shorter than 5 s
    q = by["car1.axle1.right.derailment"]
    assert q.terms == (("car1.axle1.force_y", 1.0),) and q.denominator == (("car1.axle1.right.force_z", 1.0),)
    assert by["car1.axle1.left.derailment"].terms == (("car1.axle1.force_y", -1.0),)
    u = by["car1.axle1.unloading"]
    assert dict(u.terms) == {"car1.axle1.right.force_z": 1.0, "car1.axle1.left.force_z": -1.0}
    # no lateral force per wheel: one lateral contact per wheelset
    assert not any(n.endswith((".left.force_y", ".right.force_y")) for n in by)
    assert derivative_name("bridge.span1.mid.disp_z") == "bridge.span1.mid.vel_z"
    assert derivative_name("car1.body.vel_rx") == "car1.body.acc_rx"
    assert derivative_name("car1.body.acc_z") is None and derivative_name("car1.axle1.force_y") is None


def test_engine_outputs_add_inputs_and_recorded_derivatives(setup):
    _, channels, _, cat = setup
    selected, derived = select_channels(channels, cat, ["bridge.span1.mid.disp_z", "bridge.span1.q1.twist_3m",
                                                         "car1.axle1.right.derailment"])
    assert [c.name for c in selected] == ["bridge.span1.mid.disp_z"]
    assert [d.name for d in derived] == ["bridge.span1.q1.twist_3m", "car1.axle1.right.derailment"]
    out = [c.name for c in engine_outputs(selected, derived, channels, cat)]
    assert out[0] == "bridge.span1.mid.disp_z" and "bridge.span1.mid.vel_z" in out
    assert {"bridge.span1.q1.rail_left_ahead.disp_z", "bridge.span1.q1.rail_right_behind.vel_z",
            "car1.axle1.force_y", "car1.axle1.right.force_z"} <= set(out)
    assert "car1.axle1.left.force_z" not in out
    wf = [c.name for c in engine_outputs(selected, derived, channels, cat, wheel_forces=True)]
    assert wf[: len(out)] == out and wf[-1] == "car1.axle1.left.force_z"
    with pytest.raises(ScenarioError, match=r"analysis.channels\[1\].*matches no channel"):
        select_channels(channels, cat, ["car1.*", "bridge.span9.*"])


@pytest.mark.exudyn
def test_twist_of_a_run_from_the_rail_displacements():
    """Problem: scenario 'quick' (ICE motor car over one 32 m span, the track 2.5 m off the girder axis:
    the eccentric load twists the deck), the deterministic run under gravity.

    Reference: the rails' vertical displacements computed here from the run's bridge modal coordinates
    q(t) and the bridge's rail shapes at x +- 1.5 m: z_L,R = (z +- b rx)(x) . q, twist = [z_L - z_R](x +
    1.5) - [z_L - z_R](x - 1.5). The channel is the same linear form of the same numbers: 1e-12 of its
    largest value (summation order)."""
    import tb_exudyn as tbx
    from tb_exudyn.builder import build_model
    from tb_exudyn.methods import run_deterministic

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("bridge.span1.*.twist_3m",)))
    model = build_model(sc, warn=False)
    th = run_deterministic(sc, model=model)
    rec = model.recording()
    q = rec.nodes[rec.bridge_node][0]
    b = sc.track.half_gauge
    stations = station_positions(model.bridge.station_names, sc.bridge.spans)
    assert set(th.names) == {f"bridge.{s}.twist_3m" for s in stations}
    for st, x in stations.items():
        rs = model.bridge.rail_shapes(np.array([x + 1.5, x - 1.5]))
        zl, zr = q @ (rs.z + b * rs.rx).T, q @ (rs.z - b * rs.rx).T
        ref = (zl[:, 0] - zr[:, 0]) - (zl[:, 1] - zr[:, 1])
        got = th[f"bridge.{st}.twist_3m"]
        assert np.max(np.abs(ref)) > 0, st
        assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(ref)), st
        assert th.unit(f"bridge.{st}.twist_3m") == "m"
