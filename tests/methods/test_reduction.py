"""The reductions of tb_exudyn.methods.reduction on synthetic pseudo-responses and samples.

Every reference is computed here from the same synthetic inputs by direct formulas (numpy sums over
columns, tb_exudyn.system.statistics.pseudo_derivative on whole histories, exact sample ratios),
independently of the reducers' incremental, sparse and covariance bookkeeping.
"""

from __future__ import annotations

import math

import numpy as np
from tb_exudyn.methods.reduction import (
    PseudoReduction,
    SampleReduction,
    finish_pem,
    finish_pem_task,
    mean_rows,
    ratio_coefficients,
    reduction_plan,
    sample_offsets,
)
from tb_exudyn.system.comfort import sperling_weighting
from tb_exudyn.system.statistics import pseudo_derivative
from tb_exudyn.system.derived import DerivedChannel

DT = 0.005
N_T = 240
T = np.arange(N_T) * DT
OUTPUTS = ("car1.body.disp_z", "car1.body.vel_z", "car1.body.acc_z", "car1.axle1.left.force_z",
           "car1.axle1.right.force_z", "car1.axle1.force_y")
SELECTED = [("car1.body.disp_z", "m"), ("car1.body.acc_z", "m/s^2"), ("car1.axle1.left.force_z", "N")]
RATIO = DerivedChannel("car1.axle1.left.derailment", "-", "ratio", (("car1.axle1.force_y", -1.0),),
                       (("car1.axle1.left.force_z", 1.0),))
UNLOAD = DerivedChannel("car1.axle1.unloading", "-", "ratio",
                        (("car1.axle1.right.force_z", 1.0), ("car1.axle1.left.force_z", -1.0)),
                        (("car1.axle1.right.force_z", 1.0), ("car1.axle1.left.force_z", 1.0)))


def _columns(n_f: int = 5, n_types: int = 2, seed: int = 0):
    """Frequency-major columns: n_f frequencies x n_types types, f in 0.7-9 Hz."""
    f = np.linspace(0.7, 9.0, n_f)
    f_col = np.repeat(f, n_types)
    types = np.tile(np.arange(n_types), n_f)
    df = np.full(n_f, 0.4)
    return f, f_col, types, df


def _pseudo_histories(f_col: np.ndarray, seed: int = 1) -> np.ndarray:
    """(n_outputs, m, n_t) complex pseudo-responses: a forced part c e^{i w t} with a slowly varying
    envelope plus a free part at another frequency (what the pseudo-derivative errs on)."""
    rng = np.random.default_rng(seed)
    m = f_col.size
    w = 2 * np.pi * f_col
    env = 1.0 + 0.5 * np.sin(2 * np.pi * 0.3 * T)[None, :] * rng.uniform(0.2, 1.0, (m, 1))
    out = np.zeros((len(OUTPUTS), m, N_T), dtype=complex)
    for j in range(len(OUTPUTS)):
        c = rng.normal(size=m) + 1j * rng.normal(size=m)
        free = 0.3 * (rng.normal(size=m) + 1j * rng.normal(size=m))[:, None] * np.exp(1j * 2 * np.pi * 4.3 * T)[None, :]
        out[j] = c[:, None] * env * np.exp(1j * w[:, None] * T[None, :]) + free * np.exp(-0.8 * T)[None, :]
    out[3:5] *= 1e3  # wheel forces around means of 8e4 N below
    out[5] *= 3e2
    return out


def _feed(reducer, hist):
    ext = np.arange(hist.shape[0])
    for i in range(N_T):
        reducer.record(i, np.ascontiguousarray(hist[:, :, i]), ext)
    return reducer.result()


def test_incremental_pseudo_derivative_equals_statistics_pseudo_derivative():
    """Problem: 10 columns (5 frequencies x 2 types) of pseudo-responses with a modulated forced part
    and a decaying free part at 4.3 Hz; channel car1.body.acc_z (no recorded derivative).

    Reference: tb_exudyn.system.statistics.pseudo_derivative on each column's whole history, then
    sum_k |yd_k|^2 and sum_k Re(conj(y_k) yd_k) per time. The reducer differences incrementally (one
    output time late, first and last times one-sided): the same arithmetic in another order, so
    agreement to 1e-12 relative; and the recorded derivative of disp_z is the vel_z channel exactly.
    """
    f, f_col, types, df = _columns()
    hist = _pseudo_histories(f_col)
    plan = reduction_plan(OUTPUTS, SELECTED, [])
    red = PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=False)
    raw = _feed(red, hist)
    fin = finish_pem_task(raw, plan, None)
    k = plan.names.index("car1.body.acc_z")
    y = hist[OUTPUTS.index("car1.body.acc_z")]
    yd = pseudo_derivative(T, y, f_col)
    ref_var = np.sum(np.abs(yd) ** 2, axis=0)
    ref_cov = np.sum(np.real(np.conj(y) * yd), axis=0)
    assert np.max(np.abs(fin["dvar"][:, k] - ref_var)) < 1e-12 * ref_var.max()
    assert np.max(np.abs(fin["dcov"][:, k] - ref_cov)) < 1e-12 * np.abs(ref_cov).max()
    kd = plan.names.index("car1.body.disp_z")
    v = hist[OUTPUTS.index("car1.body.vel_z")]
    assert np.allclose(fin["dvar"][:, kd], np.sum(np.abs(v) ** 2, axis=0), rtol=1e-13, atol=0)
    assert plan.derivative_sources()["car1.body.disp_z"].startswith("recorded")
    assert plan.derivative_sources()["car1.body.acc_z"].startswith("pseudo")
    # sigma^2 by type and the PSD map are the plain sums
    var_ref = np.stack([np.sum(np.abs(y[types == ti]) ** 2, axis=0) for ti in range(2)])
    assert np.allclose(fin["var_t"][:, :, k].T, var_ref, rtol=1e-13)


def test_ratios_to_first_order_from_the_covariances_of_their_parts():
    """Problem: Q/P = -H / P_L and dP/P = (P_R - P_L)/(P_R + P_L) of synthetic pseudo-responses about
    means P_L(t), P_R(t) ~ 8e4 N varying in time and H(t) ~ 2e3 N.

    Reference: the first-order ratio's pseudo-responses formed column by column in the test,
    r_k = N_k / D - N D_k / D^2 (means N, D), and its derivative r'_k = a N'_k + b D'_k + a' N_k + b' D_k
    with N'_k, D'_k from statistics.pseudo_derivative and a = 1/D, b = -N/D^2, a', b' from the means'
    numpy.gradient; then sigma^2 by type, the PSD, sum |r'_k|^2, sum Re(conj r_k r'_k) and the
    spectral moments directly. The reducer gets them from the parts' covariances summed over
    columns: algebraically equal, so 1e-9 relative (PSD: float32 transport, 1e-6).
    """
    f, f_col, types, df = _columns()
    hist = _pseudo_histories(f_col, seed=4)
    plan = reduction_plan(OUTPUTS, SELECTED, [RATIO, UNLOAD])
    red = PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=True)
    raw = _feed(red, hist)
    means = np.zeros((len(OUTPUTS), N_T))
    means[3] = 8.0e4 + 3e3 * np.sin(2 * np.pi * 0.5 * T)
    means[4] = 7.6e4 - 2e3 * np.cos(2 * np.pi * 0.7 * T)
    means[5] = 2e3 * np.sin(2 * np.pi * 0.4 * T)
    rows = mean_rows(plan, means, T)
    coef = ratio_coefficients(plan, rows)
    fin = finish_pem_task(raw, plan, coef)
    w = 2 * np.pi * f_col
    for d in (RATIO, UNLOAD):
        k = plan.names.index(d.name)
        idx = {n: OUTPUTS.index(n) for n in d.inputs}
        Nk = sum(c * hist[idx[n]] for n, c in d.terms)
        Dk = sum(c * hist[idx[n]] for n, c in d.denominator)
        Nm = sum(c * means[idx[n]] for n, c in d.terms)
        Dm = sum(c * means[idx[n]] for n, c in d.denominator)
        a, b = 1 / Dm, -Nm / Dm**2
        Nr, Dr = np.gradient(Nm, T), np.gradient(Dm, T)
        ar, br = -Dr / Dm**2, -Nr / Dm**2 + 2 * Nm * Dr / Dm**3
        r = a * Nk + b * Dk
        rd = a * pseudo_derivative(T, Nk, f_col) + b * pseudo_derivative(T, Dk, f_col) + ar * Nk + br * Dk
        var_ref = np.stack([np.sum(np.abs(r[types == ti]) ** 2, axis=0) for ti in range(2)])
        assert np.allclose(fin["var_t"][:, :, k].T, var_ref, rtol=1e-9, atol=0), d.name
        assert np.allclose(fin["dvar"][:, k], np.sum(np.abs(rd) ** 2, axis=0), rtol=1e-9, atol=0), d.name
        cov = np.sum(np.real(np.conj(r) * rd), axis=0)
        assert np.max(np.abs(fin["dcov"][:, k] - cov)) < 1e-9 * np.abs(cov).max(), d.name
        lam_ref = np.stack([np.sum(w[:, None] ** p * np.abs(r) ** 2, axis=0) for p in (1, 2)])
        assert np.allclose(fin["lam"][:, :, k].T, lam_ref, rtol=1e-9), d.name
        psd_ref = (np.abs(r) ** 2).reshape(f.size, 2, N_T).sum(axis=1) / df[:, None]
        assert np.max(np.abs(fin["psd"][k] - psd_ref)) < 1e-6 * psd_ref.max(), d.name


def test_sperling_channel_of_a_harmonic_from_pem_and_from_samples():
    """Problem: a car-body acceleration that is a harmonic of amplitude A = 0.3 m/s^2 at 2.5 Hz,
    Sperling Wz over 2 s windows; PEM as one column a e^{i w t} with |a|^2 = A^2 / 2 (the variance of a
    harmonic of random phase), Monte Carlo as 4 samples A cos(w t + phi) with whole periods per window.

    Reference: Sperling's single-frequency formula Wz = (B(f) * 100 A)^0.3 with
    B(f) = 0.588 sqrt((1.911 f^2 + (0.25 f^2)^2) / ((1 - 0.277 f^2)^2 + (1.563 f - 0.0368 f^3)^2))
    typed here. PEM: exact (1e-12). Monte Carlo: the periodogram of whole periods puts the harmonic in
    one bin of a rectangular window (no leakage), exact to round-off (1e-10); every sample's index is
    the same, so the channel's sample sigma is 0 to round-off.
    """
    A, fh, window = 0.3, 2.5, 2.0
    B = 0.588 * math.sqrt((1.911 * fh**2 + (0.25 * fh**2) ** 2) / ((1 - 0.277 * fh**2) ** 2 + (1.563 * fh - 0.0368 * fh**3) ** 2))
    assert abs(B / float(sperling_weighting(fh)) - 1) < 1e-14
    expected = (B * 100 * A) ** 0.3
    sp = DerivedChannel("car1.body.sperling_z", "-", "sperling", (("car1.body.acc_z", 1.0),), weighting="vertical",
                        window=window)
    outputs = ("car1.body.acc_z",)
    plan = reduction_plan(outputs, [("car1.body.acc_z", "m/s^2")], [sp])
    n_t = 400  # 2 s windows at 200 Hz: 2 whole windows
    t = np.arange(n_t) * DT
    f_col = np.array([fh])
    red = PseudoReduction(plan, f_col, np.array([0]), 1, 1, np.array([0.1]), n_t, DT, keep_psd=False)
    a = A / math.sqrt(2) * np.exp(1j * 2 * np.pi * fh * t)
    for i in range(n_t):
        red.record(i, a[None, None, i].reshape(1, 1), np.array([0]))
    raw = red.result()
    fin = finish_pem_task(raw, plan, None)
    mean = np.zeros((2, n_t))
    rows = mean_rows(plan, np.zeros((1, n_t)), t)
    st = finish_pem(plan, mean, t, rows, None, fin["var_t"].sum(axis=1).T, fin["dvar"], fin["dcov"], fin["lam"],
                    fin["sperling_power"])
    k = plan.names.index("car1.body.sperling_z")
    assert np.max(np.abs(st.mean[k] / expected - 1)) < 1e-12
    # Monte Carlo: samples A cos(w t + phi)
    phases = np.array([0.1, 1.3, 2.9, 4.4])
    samples = A * np.cos(2 * np.pi * fh * t[None, :] + phases[:, None])  # (n, n_t)
    red_mc = SampleReduction(plan, np.zeros(0, dtype=np.int64), n_t, phases.size, False, None, None, 1 / DT)
    for i in range(n_t):
        Y = np.zeros((1, (phases.size + 1) // 2), dtype=complex)
        Y.view(np.float64)[0, : phases.size] = samples[:, i]
        red_mc.record(i, Y, np.array([0]))
    out = red_mc.result()
    assert np.max(np.abs(out["mean"][k] / expected - 1)) < 1e-10
    assert np.max(out["m2"][k]) < 1e-20
    assert np.allclose(out["sample_max"][:, k], expected, rtol=1e-10)
    assert np.allclose(sample_offsets(plan, np.ones((2, n_t)))[k], 0.0)


def test_sample_ratios_and_extremes_are_of_the_totals():
    """Problem: 6 samples of (P_L, P_R, H) deviations about means, a linear engine's view (the reducer
    gets deviations and the mean run's rows).

    Reference: the exact ratios of the totals (mean + deviation) sample by sample, their mean and sum
    of squared deviations about the mean run's ratio, and every sample's min and max over time of
    every channel, all computed here with numpy (1e-12 relative).
    """
    rng = np.random.default_rng(7)
    n = 6
    dev = rng.normal(size=(len(OUTPUTS), n, N_T)) * np.array([1e-3, 1e-2, 0.1, 4e3, 4e3, 2e3])[:, None, None]
    means = np.zeros((len(OUTPUTS), N_T))
    means[3], means[4] = 8.0e4, 7.8e4 + 100 * np.sin(T)
    plan = reduction_plan(OUTPUTS, SELECTED, [RATIO, UNLOAD])
    rows = mean_rows(plan, means, T)
    det = np.zeros((len(plan.names), N_T))
    for k, (name, _) in enumerate(SELECTED):
        det[k] = means[OUTPUTS.index(name)]
    for d in (RATIO, UNLOAD):
        det[plan.names.index(d.name)] = (sum(c * means[OUTPUTS.index(x)] for x, c in d.terms)
                                         / sum(c * means[OUTPUTS.index(x)] for x, c in d.denominator))
    force_rows = np.array([3, 4], dtype=np.int64)
    red = SampleReduction(plan, force_rows, N_T, n, False, sample_offsets(plan, det), rows.value, 1 / DT,
                          means[force_rows])
    for i in range(N_T):
        Y = np.zeros((len(OUTPUTS), (n + 1) // 2), dtype=complex)
        Y.view(np.float64)[:, :n] = dev[:, :, i]
        red.record(i, Y, np.arange(len(OUTPUTS)))
    out = red.result()
    tot = dev + means[:, None, :]
    for d in (RATIO, UNLOAD):
        k = plan.names.index(d.name)
        r = (sum(c * tot[OUTPUTS.index(x)] for x, c in d.terms) / sum(c * tot[OUTPUTS.index(x)] for x, c in d.denominator))
        dv = r - det[k]
        assert np.allclose(out["mean"][k], dv.mean(axis=0), rtol=1e-12, atol=1e-15)
        assert np.allclose(out["m2"][k], ((dv - dv.mean(axis=0)) ** 2).sum(axis=0), rtol=1e-10, atol=1e-18)
        assert np.allclose(out["sample_min"][:, k], r.min(axis=1), rtol=1e-12)
        assert np.allclose(out["sample_max"][:, k], r.max(axis=1), rtol=1e-12)
    k = plan.names.index("car1.axle1.left.force_z")
    assert np.allclose(out["sample_max"][:, k], tot[3].max(axis=1), rtol=1e-12)
    assert np.allclose(out["min_force"], tot[3:5].min(axis=(0, 2)), rtol=1e-12)


def test_plan_dedupes_rows_and_names_every_derivative():
    """The plan's internal rows: one per distinct linear form (a channel used as an input and as a
    result is one row); every result channel says where its derivative comes from."""
    wb = DerivedChannel("car1.body.acc_z_wb", "m/s^2", "weighted", (("car1.body.acc_z", 1.0),), weighting="wb")
    sp = DerivedChannel("car1.body.sperling_z", "-", "sperling", (("car1.body.acc_z", 1.0),), weighting="vertical",
                        window=1.0)
    plan = reduction_plan(OUTPUTS, SELECTED, [wb, sp, RATIO])
    # rows: disp_z, acc_z, left.force_z, acc_z (wb), -force_y; sperling reuses acc_z's row
    assert plan.n_z == 5
    assert plan.sperling[0][1] == plan.result_z[plan.names.index("car1.body.acc_z")]
    assert set(plan.derivative_sources()) == set(plan.names)
    assert plan.derivative_sources()["car1.body.sperling_z"].startswith("none")


def _plain_pem_sums(plan, hist, f_col, types, n_types, df):
    """The PEM sums of the module docstring written plainly from L @ y[ext] per time: sigma^2 by type,
    the PSD map (per Hz, summed over types) and the ratios' cross sums by type."""
    n_f = df.size
    var, psd, nd = [], [], []
    zn = [r[1] for r in plan.ratios]
    zd = [r[2] for r in plan.ratios]
    for i in range(hist.shape[2]):
        Z = np.asarray(plan.L @ hist[:, :, i])
        P = Z.real**2 + Z.imag**2
        var.append(np.stack([P[:, types == t].sum(axis=1) for t in range(n_types)]))
        psd.append(P.reshape(P.shape[0], n_f, -1).sum(axis=2) / df)
        X = (Z[zn].conj() * Z[zd]).real
        nd.append(np.stack([X[:, types == t].sum(axis=1) for t in range(n_types)]))
    return np.array(var), np.moveaxis(np.array(psd), 0, 2), np.array(nd)


def test_reducer_in_its_own_row_order_gives_the_plain_sums():
    """Problem: the reducer reads the engine's outputs in the engine's row order (``ext``, here a
    random permutation: the batched engine's internal channel order), forms the z rows in its own
    order (recorded-derivative rows, pseudo-derivative rows, the rest; within each, the rows that
    copy one output first, gathered, the others by the sparse map) and keeps the last three times by
    reference. Reference: the plain sums of L @ y[ext] per time written in this test (sigma^2 by type,
    the PSD map, the ratios' cross sums by type) and, for the derivative's sums, the same reducer fed
    in the identity order. The operations per value are the same, so sigma^2 and the cross sums agree
    to round-off of the summation over columns (1e-13 relative); the derivative's sums are bitwise
    equal between the two row orders. The PSD travels as float32 (1e-6)."""
    f, f_col, types, df = _columns(n_f=6)
    hist = _pseudo_histories(f_col, seed=7)
    plan = reduction_plan(OUTPUTS, SELECTED, [RATIO, UNLOAD])
    ext = np.random.default_rng(3).permutation(len(OUTPUTS))
    red = PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=True)
    for i in range(N_T):  # the engine's row ext[k] holds output k
        Y = np.empty_like(hist[:, :, i])
        Y[ext] = hist[:, :, i]
        red.record(i, Y, ext)
    raw = red.result()
    var, psd, nd = _plain_pem_sums(plan, hist, f_col, types, 2, df)
    assert np.max(np.abs(raw["var_z"] - var)) <= 1e-13 * np.abs(var).max()
    assert np.max(np.abs(raw["nd_type"] - nd)) <= 1e-13 * np.abs(nd).max()
    assert np.max(np.abs(raw["psd_z"] - psd)) <= 1e-6 * np.abs(psd).max()
    same = _feed(PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=True), hist)
    for key in ("var_z", "dvar_z", "dcov_z", "nd_pairs", "lam_z", "nd_lam", "psd_z"):
        assert np.array_equal(raw[key], same[key]), key


def test_variance_only_reduction_is_the_full_one_for_sigma():
    """Problem: the grid error's midpoint sweep needs sigma^2 only (by type, ratios through their
    parts' cross sums). Reference: the full reduction of the same columns. sigma^2 by type and the
    ratios' cross sums are the same operations on the same values: bitwise equal; everything else
    stays zero."""
    f, f_col, types, df = _columns()
    hist = _pseudo_histories(f_col, seed=5)
    plan = reduction_plan(OUTPUTS, SELECTED, [RATIO, UNLOAD])
    full = _feed(PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=False), hist)
    var_only = _feed(PseudoReduction(plan, f_col, types, 2, f.size, df, N_T, DT, keep_psd=False,
                                     variance_only=True), hist)
    assert np.array_equal(var_only["var_z"], full["var_z"]) and np.array_equal(var_only["nd_type"], full["nd_type"])
    for key in ("dvar_z", "dcov_z", "lam_z", "nd_lam", "nd_pairs", "sperling_power"):
        assert not np.any(var_only[key]), key
