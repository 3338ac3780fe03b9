"""The irregularity taper: inputs start at zero with zero slope and rise smoothly (pure numpy)."""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.system.excitation import HarmonicExcitation, ProfileExcitation, rail_inputs, taper


def test_taper_is_zero_before_and_one_after_and_c1():
    """w(x) = (1 - cos(pi s / L)) / 2 on s = x - x_ref in [0, L]: values 0, 1/2, 1 at s = 0, L/2, L
    (exact); the slope equals a central finite difference to O(h^2) = 1e-8 with h = 1e-4 m."""
    x = np.array([-130.0, -100.0, -90.0, -80.0, 0.0])
    w, dw = taper(x, -100.0, 20.0)
    assert np.allclose(w, [0.0, 0.0, 0.5, 1.0, 1.0], atol=1e-15)
    assert dw[2] == pytest.approx(np.pi / 40.0, rel=1e-14)
    xs = np.linspace(-101.0, -79.0, 57)
    h = 1e-4
    fd = (taper(xs + h, -100.0, 20.0)[0] - taper(xs - h, -100.0, 20.0)[0]) / (2 * h)
    assert np.allclose(taper(xs, -100.0, 20.0)[1], fd, atol=1e-8)


@pytest.mark.parametrize("exc", [
    HarmonicExcitation(kind="vertical", spatial_frequency=0.7, amplitude=1e-3, part="real"),
    ProfileExcitation(alignment=lambda x: (1e-3 * np.cos(x), -1e-3 * np.sin(x))),
])
def test_inputs_at_the_start_are_zero_and_later_untouched(exc):
    """Every wheel at or behind x_ref sees zero input and slope (a run starts in equilibrium);
    past the taper the input is the excitation itself (product rule: slope w' v + w s)."""
    behind = np.array([-150.0, -120.0, -100.0])
    val, slo = rail_inputs(exc, behind, -100.0, 0.75, taper_length=20.0)
    assert np.all(val == 0.0) and np.all(slo == 0.0)
    far = np.array([-50.0, 3.0, 40.0])
    tapered = rail_inputs(exc, far, -100.0, 0.75, taper_length=20.0)
    plain = rail_inputs(exc, far, -100.0, 0.75, taper_length=0.0)
    assert np.array_equal(tapered[0], plain[0]) and np.array_equal(tapered[1], plain[1])
