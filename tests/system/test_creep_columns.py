"""The column sources' inputs of the general linear rows (creep: alignment and cross-level as rail
motion) against the coupling's own evaluation for one real run (tb_exudyn.system.columns)."""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.system.columns import HarmonicColumns, ProfileColumns, linear_row_inputs
from tb_exudyn.system.excitation import KINDS, HarmonicExcitation

from .test_creep_coupling import B, _coupling

TIMES = (0.02, 0.25, 0.5, 0.9)  # taper rising (the first axle starts at -3 m, taper 8 m), then on the bridge


def _with_taper(excitation=None):  # noqa: ANN001
    cp = _coupling(True, excitation)
    cp.taper_length = 8.0
    return cp


def test_harmonic_columns_give_the_coupling_input_forces():
    """Exact problem: the wheelset of test_creep_coupling (creep rows with spin and a gravitational
    yaw stiffness, so that every input weight is nonzero) with an 8 m taper, one column per kind at
    0.4 rad/m with pseudo-amplitudes 1e-3 (cross-level given as a height: scale 1 / 2b).

    Reference: the coupling's input force f_in = W^v . val + W^s . slope of the real (cosine) and
    imaginary (sine) runs of each column, set as its excitation (rail_inputs, taper included): the
    column's complex input is real run + i imaginary run. Tolerance 1e-12 of the largest force: the
    same products in another order."""
    omega = np.full(3, 0.4)
    units = ("angle", "angle", "height")
    scale = np.array([1.0, 1.0, 1.0 / (2 * B)])
    cols = HarmonicColumns(kinds=np.arange(3), omega=omega, amplitude=np.full(3, 1e-3), units=units,
                           scale=scale, type_index=np.arange(3), freq_index=np.zeros(1, dtype=np.int64),
                           df=np.ones(1), n_types=3)
    cp = _with_taper()
    for t in TIMES:
        got = linear_row_inputs(cols, cp, t)
        assert got.shape == (cp.n_linear, 3)
        for j, kind in enumerate(KINDS):
            ref = []
            for part in ("real", "imag"):
                cp.set_excitation(HarmonicExcitation(kind=kind, spatial_frequency=0.4, amplitude=1.0, part=part,
                                                     cross_level_unit=units[j]))
                ref.append(cp.contact_state(t).f_lin.copy())
            want = ref[0] + 1j * ref[1]
            scale_ = np.abs(want).max()
            if kind == "vertical":  # the creep rows take no vertical input
                assert not np.any(got[:, j]) and scale_ == 0.0
                continue
            assert scale_ > 0.0
            assert np.abs(got[:, j] - want).max() <= 1e-12 * scale_, (t, kind)


def test_profile_columns_give_the_coupling_input_forces():
    """Exact problem: three sampled profiles per kind (random, seed 4) on a 0.25 m grid, cross-level
    as a height, the same wheelset and taper. Reference: each sample alone as the coupling's
    excitation (``ProfileColumns.excitation``: the same spline), its f_lin; column j holds samples 2j
    (real part) and 2j + 1 (imaginary part; the odd count is padded with a zero sample). Tolerance
    1e-12 of the largest force."""
    rng = np.random.default_rng(4)
    x0, dx, n = -40.0, 0.25, 400
    grids = {k: rng.normal(size=(n, 3)) * 1e-3 for k in KINDS}
    cols = ProfileColumns(grids, x0, dx, "height", B)
    cp = _with_taper()
    for t in TIMES:
        got = linear_row_inputs(cols, cp, t)
        assert got.shape == (cp.n_linear, 2)
        ref = []
        for s in range(3):
            cp.set_excitation(cols.excitation(s))
            ref.append(cp.contact_state(t).f_lin.copy())
        want = np.stack([ref[0] + 1j * ref[1], ref[2] + 0j], axis=1)
        assert np.abs(want).max() > 0.0
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max(), t


def test_sources_without_general_rows_give_no_rows():
    """Exact problem: the coupling without creep rows. Reference: no general rows, so an empty
    (0, m) input for both sources (the dense engine then adds nothing). Exact."""
    cp = _coupling(False)
    cols = HarmonicColumns(kinds=np.array([1]), omega=np.array([0.4]), amplitude=np.array([1e-3]), units=("angle",),
                           scale=np.ones(1), type_index=np.zeros(1, dtype=np.int64), freq_index=np.zeros(1, dtype=np.int64),
                           df=np.ones(1), n_types=1)
    assert linear_row_inputs(cols, cp, 0.3).shape == (0, 1)
    prof = ProfileColumns({"alignment": np.zeros((10, 2))}, -10.0, 1.0, "angle", B)
    assert linear_row_inputs(prof, cp, 0.3).shape == (0, 1)


@pytest.mark.parametrize("t", [0.05, 0.5])
def test_unit_input_forces_are_the_forces_of_a_unit_input(t):
    """Exact problem: the wheelset with creep rows at a time on the approach and one on the bridge.
    Reference: the coupling's generalised force at u = 0 (``forces``) for an excitation that is a
    unit value (constant profile 1) or a unit slope (profile x - x_a, zero at the axle) of one kind
    at the axle, rate = v slope; no taper, no point loads. Tolerance 1e-12 of the largest force."""
    from tb_exudyn.system.excitation import ProfileExcitation

    cp = _coupling(True)
    x_a = float(cp.positions(t)[0])
    U = cp.unit_input_forces(t)
    assert U.shape == (3, cp.n, 2)
    zero = np.zeros(cp.n)
    for k, kind in enumerate(KINDS):
        for col, prof in ((0, lambda x: (np.ones_like(x), np.zeros_like(x))),
                          (1, lambda x: (x - x_a, np.ones_like(x)))):
            cp.set_excitation(ProfileExcitation(**{kind: prof}))
            Q = cp.forces(t, zero, zero)
            assert np.abs(U[k, :, col] - Q).max() <= 1e-12 * max(np.abs(Q).max(), 1.0), (kind, col)
