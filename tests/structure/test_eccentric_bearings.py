"""Why a girder on bearings below its axis has a first vertical frequency below the closed form (issue 49).

Problem: one simply supported span (a ``frame`` of one span: abutments only), its bearings h below the
girder axis, fixed lengthwise at one end and sliding at the other. As the span bends its end rotates by
theta about the fixed bearing, so the whole girder moves along the bridge by h theta and its mass m L moves
lengthwise too. With the sine shape w = a sin(pi x / L) (theta = pi a / L) the kinetic energy gains
m L (h pi a / L)^2 / 2 against the bending mode's m L a^2 / 4: the modal mass grows by 2 pi^2 (h / L)^2, and
Rayleigh's quotient gives f1 = f_ss / sqrt(1 + 2 pi^2 (h / L)^2), f_ss = pi / (2 L^2) sqrt(E I / m).

Reference: that closed form. Rayleigh's quotient with an assumed shape is an upper bound of the lowest
frequency, so the FE value must lie below it; the true shape adapts only a little for h / L of a few
per cent, hence within 1 % of it (measured: 0.2 % at h / L = 0.05, 0.5 % at 0.072). With the bearings at
the axis (h = 0) the FE value is the closed form to the mesh's accuracy (1e-4: 16 elements per span)."""

from __future__ import annotations

import math

import pytest

from tb_exudyn.cli.show import frequency_rows, hand_f1
from tb_exudyn.scenario.io import load_bridge
from tb_exudyn.structure import modal_bridge
from tb_exudyn.system.modes import nth_frequency


def _f1(bridge) -> float:
    mb = modal_bridge(bridge, 30.0, 0)
    return nth_frequency(mb.frequencies, mb.mode_types, "vertical", 1)


@pytest.mark.parametrize("h", [0.0, 1.6, 2.3])
def test_f1_on_bearings_below_the_axis_against_rayleigh(h):
    base = load_bridge("li_zhu_2011_bridge")
    span = 32.0
    bridge = base.replace(spans=(span,), bearings=base.bearings.replace(height=h))
    g = bridge.girder
    f_ss = math.pi / (2 * span ** 2) * math.sqrt(g.E * g.I_y / (g.mass_per_length + bridge.added_mass.mass_per_length))
    assert hand_f1(bridge)[0] == pytest.approx(f_ss, rel=1e-12)
    rayleigh = f_ss / math.sqrt(1 + 2 * math.pi ** 2 * (h / span) ** 2)
    fe = _f1(bridge)
    if h == 0.0:
        assert fe == pytest.approx(f_ss, rel=1e-4)
    else:
        assert rayleigh * 0.99 < fe < rayleigh


def test_the_show_row_splits_the_difference_by_computing():
    """li_zhu_2011_bridge: the row names the bearings' share with the FE f1 at the axis it computed."""
    bridge = load_bridge("li_zhu_2011_bridge")
    rows = {k: (v, d) for k, v, _, d in frequency_rows(bridge)}
    at_axis = _f1(bridge.replace(bearings=bridge.bearings.replace(height=0.0)))
    value, why = rows["FE against closed form"]
    assert value == "-5.4 %" and f"{at_axis:.3f} Hz" in why and "bearings 2.3 m below the girder axis" in why
