"""The PEM reducer's compiled path (tb_exudyn/methods/compiled_reduction.py) against its numpy path.

Both paths of :class:`~tb_exudyn.methods.pseudo_reduction.PseudoReduction` get the same synthetic
pseudo-responses (seeded, in a permuted engine row order) on a plan with every kind of row: plain
channels, a linear combination of outputs, an EN 12299 weighted channel (weighted rows, some with a
recorded derivative), two ratios (their cross sums and derivative pairs), a Sperling channel; 1, 2
and 3 irregularity types per frequency (the compiled path's general loop and its unrolled loop for
three types). The numpy path is the reference (it is the plain formulas' code, tested against them in
tests/methods/test_reduction.py).

Tolerances: the two paths form the same z rows (the same terms in the same order) and differ only in
the order of the sums over the columns (numpy: BLAS and pairwise summation; compiled: reassociated
and vectorised), so every sum agrees to a few ulps of its terms' magnitude: 1e-13 of the largest
value of each quantity. The cross sums Re(conj(a) b) (dcov, the ratios' sums) can cancel, so they are
compared against the Cauchy-Schwarz scale sqrt(sum |a|^2 sum |b|^2) of the same row and time. The
PSD maps travel as float32: within one float32 rounding (1e-6 relative to the map's largest value).
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.methods.reduction import PseudoReduction, reduction_plan
from tb_exudyn.system.derived import DerivedChannel

DT = 0.005
N_T = 40
OUTPUTS = ("car1.body.disp_z", "car1.body.vel_z", "car1.body.acc_z", "car1.body.acc_y", "car1.axle1.left.force_z",
           "car1.axle1.right.force_z", "car1.axle1.force_y", "car1.axle2.force_y", "car1.axle2.left.force_z")
SELECTED = [("car1.body.disp_z", "m"), ("car1.body.acc_z", "m/s^2"), ("car1.body.acc_y", "m/s^2"),
            ("car1.axle1.left.force_z", "N"), ("car1.axle2.force_y", "N")]
DERIVED = [
    DerivedChannel("car1.axle1.left.derailment", "-", "ratio", (("car1.axle1.force_y", -1.0),),
                   (("car1.axle1.left.force_z", 1.0),)),
    DerivedChannel("car1.axle1.unloading", "-", "ratio",
                   (("car1.axle1.right.force_z", 1.0), ("car1.axle1.left.force_z", -1.0)),
                   (("car1.axle1.right.force_z", 1.0), ("car1.axle1.left.force_z", 1.0))),
    DerivedChannel("car1.body.acc_z_wb", "m/s^2", "weighted", (("car1.body.acc_z", 1.0),), weighting="wb"),
    DerivedChannel("car1.body.acc_y_wd", "m/s^2", "weighted", (("car1.body.acc_y", 1.0),), weighting="wd"),
    DerivedChannel("car1.body.sperling_z", "-", "sperling", (("car1.body.acc_z", 1.0),), weighting="vertical",
                   window=0.1),
    DerivedChannel("car1.axles.force_y", "N", "linear", (("car1.axle1.force_y", 0.5), ("car1.axle2.force_y", 0.5))),
]
CROSS = ("dcov_z", "nd_type", "nd_lam", "nd_pairs")


def _inputs(n_types: int, n_f: int = 7, seed: int = 0):
    """Frequency-major columns (n_f frequencies in 0.6-12 Hz, n_types types each), the engine's row
    order (a permutation) and (n_t, n_outputs, m) complex responses in that order."""
    rng = np.random.default_rng(seed)
    f = np.linspace(0.6, 12.0, n_f)
    f_col, types = np.repeat(f, n_types), np.tile(np.arange(n_types), n_f)
    ext = rng.permutation(len(OUTPUTS))
    Y = rng.normal(size=(N_T, len(OUTPUTS), f_col.size)) + 1j * rng.normal(size=(N_T, len(OUTPUTS), f_col.size))
    Y *= np.exp(1j * 2 * np.pi * f_col * DT)[None, None, :] ** np.arange(N_T)[:, None, None]  # harmonic in time
    return f_col, types, n_f, np.full(n_f, 0.3), ext, Y


def _run(compiled: bool, n_types: int, psd_z=None, variance_only: bool = False, types=None, seed: int = 0,
         node_weight=None):
    plan = reduction_plan(OUTPUTS, SELECTED, DERIVED)
    f_col, t0, n_f, df, ext, Y = _inputs(n_types, seed=seed)
    red = PseudoReduction(plan, f_col, t0 if types is None else types, n_types, n_f, df, N_T, DT, True, psd_z,
                          variance_only, compiled=compiled, node_weight=node_weight)
    for i in range(N_T):
        red.record(i, Y[i], ext)
    return red, red.result()


def _compare(a: dict, b: dict, d_rows: np.ndarray) -> None:
    assert a.keys() == b.keys()
    for key in a:
        x, y = np.asarray(a[key], dtype=float), np.asarray(b[key], dtype=float)
        assert x.shape == y.shape, key
        if key in CROSS or not x.size:
            continue
        tol = (1e-6 if key.endswith("psd") or key == "psd_z" else 1e-13) * max(np.abs(x).max(), 1e-300)
        assert np.max(np.abs(x - y)) <= tol, (key, np.max(np.abs(x - y)) / np.abs(x).max())
    # dcov against its Cauchy-Schwarz scale sqrt(sum |z|^2 sum |z'|^2) of the same row (d_rows: the
    # z row of each derivative column), the ratios' sums against their quantity's largest |value| and
    # the largest sum |z|^2 of the rows (their Cauchy-Schwarz scale is at most that)
    scale = np.sqrt(a["var_z"].sum(axis=1)[:, d_rows] * a["dvar_z"]).max(axis=0)
    assert np.all(np.abs(a["dcov_z"] - b["dcov_z"]) <= 1e-13 * scale), "dcov_z"
    for key in ("nd_type", "nd_lam", "nd_pairs"):
        s = np.abs(a[key]).max() + np.abs(a["var_z"]).max() + np.abs(a["lam_z"]).max() * (key == "nd_lam") \
            + np.abs(a["dvar_z"]).max() * (key == "nd_pairs")
        assert np.max(np.abs(a[key] - b[key])) <= 1e-13 * s, key


@pytest.mark.parametrize("n_types", [1, 2, 3])
def test_compiled_reducer_equals_numpy_reducer(n_types):
    """Problem: every sum of a reduction with all kinds of rows, in the engine's own row order, 1-3
    types. Reference: the numpy path on the same inputs; tolerances in the module docstring."""
    red, got = _run(True, n_types)
    assert red.kernels is not None  # the compiled path ran
    ref_red, ref = _run(False, n_types)
    assert ref_red.kernels is None
    assert red.n_rec and red.n_d > red.n_rec and red.w_at.size and red.ratio_n.size and red.sp_rows.size
    _compare(got, ref, red.d_rows)
    assert np.abs(got["nd_pairs"]).max() > 0 and np.abs(got["sperling_power"]).max() > 0


def test_compiled_reducer_with_kept_psd_rows_and_variance_only():
    """Problem: the PSD maps of some z rows only (pem.psd_z_rows), and the grid error's sigma-only
    reduction. Reference: the numpy path; the kept rows' maps equal those rows of the full map (the
    same sums), for both paths; variance only: sigma^2 by type and the ratios' type sums as in the full
    reduction (the compiled path computes them with the same code in both: bitwise), the rest zero."""
    keep = np.array([4, 1, 7])
    for compiled in (True, False):
        _, part = _run(compiled, 3, psd_z=keep)
        _, full = _run(compiled, 3)
        assert np.array_equal(part["psd_z_rows"], keep)
        assert np.array_equal(part["psd_z"], full["psd_z"][keep]), compiled
    red, got = _run(True, 3, psd_z=keep)
    _compare(got, _run(False, 3, psd_z=keep)[1], red.d_rows)
    _, vo = _run(True, 3, variance_only=True)
    _, full = _run(True, 3)
    assert np.array_equal(vo["var_z"], full["var_z"]) and np.array_equal(vo["nd_type"], full["nd_type"])
    for key in ("dvar_z", "dcov_z", "lam_z", "nd_lam", "nd_pairs", "sperling_power", "psd_z", "nd_psd"):
        assert not np.any(vo[key]), key
    _compare(vo, _run(False, 3, variance_only=True)[1], red.d_rows)


@pytest.mark.parametrize("n_types", [2, 3])
def test_node_sums_of_the_local_grid_error_estimate(n_types):
    """Problem: the local grid-error estimate's node sums (sigma^2 and the ratios' cross sums by type,
    each column weighted by its node factor). References: with every factor 1 they are the plain type
    sums (the same operations in the same order: bitwise, both paths); with factors 0.5 on some
    frequencies and 0 on the others, the compiled path against the numpy path (1e-13 of the largest
    value, module docstring) and the numpy path against its own type sums of the weighted columns
    (the factor is exact in binary: 0.5 x |z|^2 summed is half the sum, to round-off 1e-13)."""
    m = 7 * n_types
    for compiled in (True, False):
        _, ones = _run(compiled, n_types, node_weight=np.ones(m))
        assert np.array_equal(ones["var_nodes_z"], ones["var_z"]) and np.array_equal(ones["nd_nodes"], ones["nd_type"])
    half = np.repeat([0.5, 0.0, 0.5, 0.5, 0.0, 0.0, 0.5], n_types)
    _, got = _run(True, n_types, node_weight=half)
    _, ref = _run(False, n_types, node_weight=half)
    for key in ("var_nodes_z", "nd_nodes"):
        assert np.max(np.abs(got[key] - ref[key])) <= 1e-13 * np.abs(ref[key]).max(), key
    assert "var_nodes_z" not in _run(True, n_types, node_weight=np.zeros(m))[1]  # no node: no sums
    # the numpy path's node sums are the type sums over the chosen frequencies, halved
    plan = reduction_plan(OUTPUTS, SELECTED, DERIVED)
    f_col, types, n_f, df, ext, Y = _inputs(n_types)
    Z = np.stack([np.asarray(plan.L @ Yi[ext]) for Yi in Y])  # (n_t, n_z, m): z = L y in z order
    chosen = half > 0
    direct = np.stack([(np.abs(Z[:, :, chosen & (types == t)]) ** 2).sum(axis=2) / 2 for t in range(n_types)], axis=1)
    w_rows = [z for z, w in enumerate(plan.weighting) if w]  # weighted rows carry W(f): compare the others
    plain = np.setdiff1d(np.arange(plan.n_z), w_rows)
    assert np.max(np.abs(ref["var_nodes_z"][:, :, plain] - direct[:, :, plain])) <= 1e-13 * np.abs(direct).max()


def test_columns_in_another_layout_take_the_numpy_path():
    """Problem: columns whose types are not in the same order at every frequency (not what
    harmonic_columns makes). Reference: the compiled path's condition (class docstring): such a
    reducer takes the numpy path and gives its sums exactly."""
    types = np.tile([0, 1], 7)
    types[2:4] = [1, 0]
    red, got = _run(True, 2, types=types)
    assert red.kernels is None
    _, ref = _run(False, 2, types=types)
    for key in got:
        assert np.array_equal(got[key], ref[key]), key


def test_a_non_finite_response_stays_non_finite():
    """Problem: a NaN in one output of one column at one time (a diverged column). Reference: IEEE
    arithmetic: every sum over that row's columns is NaN at that time; the compiled path's fast-math
    flags (reassociation, contraction) assume no finite values, so they must not hide it."""
    plan = reduction_plan(OUTPUTS, SELECTED, DERIVED)
    f_col, types, n_f, df, ext, Y = _inputs(3)
    k0 = int(np.flatnonzero(ext == 0)[0])  # the output in the engine's row 0
    Y[5, 0, 4] = np.nan  # that row, column 4 (type 1), time 5
    red = PseudoReduction(plan, f_col, types, 3, n_f, df, N_T, DT, True)
    for i in range(N_T):
        red.record(i, Y[i], ext)
    out = red.result()
    z = np.flatnonzero(np.asarray(plan.L.tocsc()[:, k0].todense()).ravel())  # the z rows reading that output
    assert z.size and np.isnan(out["var_z"][5, :, z]).any(axis=1).all() and np.isnan(out["lam_z"][5][:, z]).all()
    assert np.isfinite(out["var_z"][4]).all()
