"""From the engines' outputs to the statistics of every result channel, derived ones included.

A result's channels are the scenario's selected channels followed by its selected derived channels
(:mod:`tb_exudyn.system.derived`). A :class:`ReductionPlan` turns an engine's outputs (rows of Y in
``outputs.names`` order) into internal rows z = L y: every result channel that is a linear form of the
outputs (a channel itself, a linear or weighted derived channel), the numerator N and denominator D of
every ratio and the input of every Sperling index (L is sparse: each row has 1 to 4 terms). What each
method does with them:

PEM (:class:`PseudoReduction`, per output time, on the complex pseudo-responses z_k of the task's
columns k; sums over columns are over frequencies and irregularity types):

- sigma^2 by type, the PSD map (per Hz), lambda_1 and lambda_2 (sum (2 pi f_k)^i |z_k|^2, for
  Vanmarcke's bandwidth) of every z row;
- a weighted channel's pseudo-response is W(f_k) z_k, W the weighting's frequency response at the
  column's excitation frequency: exact for a response at f_k with a steady amplitude (stationary
  parts), approximate where the amplitude changes within the filter's memory (the 0.4 Hz high-pass of
  Wb and Wd remembers about 1 / (2 pi 0.4 Hz / sqrt 2) = 0.56 s) and for the filter's start-up from
  rest (Monte Carlo filters each sample in time from t = 0: the difference is that start-up and the
  spread of a modulated response around f_k);
- the time derivative z'_k of every result row and ratio part, for the Rice rate: the recorded
  derivative where the model records one (a ``disp`` channel: the ``vel`` channel of the same
  coordinate; a ``vel`` channel: its ``acc``; a twist: the same combination of the rails' velocities:
  exact), otherwise :func:`tb_exudyn.system.statistics.pseudo_derivative` done incrementally
  (accelerations, forces, weighted and truncated-mode channels): demodulated by exp(-i 2 pi f_k t),
  differenced to second order, modulated back. That is exact for the forced part of z_k at f_k and
  errs by about (2 pi (nu - f_k) dt)^2 / 6 on a part oscillating at another frequency nu (free
  vibration of a mode excited at f_k), dt the output step: at dt = 0.01 s, 2 % for |nu - f_k| = 3.5 Hz,
  16 % for 10 Hz. The statistics of z' come one output time late (central differences need the next
  time), the last time by a backward difference;
- ratios N/D to first order about the means: the parent gets the covariances of (N, D, N', D')
  summed over columns and forms, with a = 1/D, b = -N/D^2 (means), sigma_r^2 = a^2 s_NN + b^2 s_DD +
  2 a b s_ND (docs/references.md, code limits), the PSD and lambda_i alike, and the derivative's statistics from
  r' = a N' + b D' + a' N + b' D;
- Sperling inputs: the B-weighted power sum_k 2 (100 B(f_k))^2 |z_k|^2 per time.

The parent (:func:`finish_pem_task`) turns a task's raw sums into per-channel arrays once the mean
is known (the mean task is reduced first).

Monte Carlo (:class:`SampleReduction`, on the real samples): linear rows directly; weighted rows and
Sperling inputs stored over the task's times and filtered in time at the end
(:func:`tb_exudyn.system.comfort.apply_weighting`: EN 12299 filters from rest) or turned into
Sperling indices per window (each sample's periodogram); ratios exactly, sample by sample, on the
totals (the deterministic mean plus the sample's response). Every channel's per-sample minimum and
maximum over the record are kept (:func:`tb_exudyn.results.empirical.sample_extremes`: what the
empirical exceedance needs). A linear engine's samples are responses about the mean: the reducer
needs the mean run's outputs (``offsets``, ``zmean``) to form totals; the result's sample moments are
of the deviation from ``offsets`` (the mean run's value of each channel, 0 for Sperling channels,
whose samples are totals).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from ..system.comfort import apply_weighting, sperling_index, sperling_power_weights, sperling_window_energy, \
    weighting_response
from ..system.derived_values import window_series
from ..system.statistics import bandwidth_from_moments
from ..system.derived import DerivedChannel, derivative_name
from .pseudo_reduction import PSD_TRANSPORT, PseudoReduction

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]

#: what a task's result holds (in the checkpoints' fingerprint: checkpoints of another layout are refused;
#: 3: the grid tasks carry the local grid-error estimate's node sums)
REDUCTION_FORMAT = 3


# ============================================================================================ the plan
@dataclass(frozen=True, eq=False)
class ReductionPlan:
    """How an engine's outputs become the result channels (module docstring).

    names, units, kinds : the result channels ('channel' for a selected channel, else the derived kind)
    L : (n_z, n_outputs) sparse: the internal rows z = L y
    Ld : (n_z, n_outputs) sparse: the recorded derivative of the rows in ``recorded`` (zero elsewhere)
    weighting : per z row, '' or the EN 12299 weighting applied to it ('wb', 'wd')
    recorded, pseudo : z rows whose time derivative is recorded / the pseudo-derivative
    result_z : (n_res,) the z row of each result channel (-1: a ratio or a Sperling index)
    ratios : (result index, z row of N, z row of D) per ratio channel
    sperling : (result index, z row of the acceleration, direction, window [s]) per Sperling channel
    derivative : per result channel, where its derivative comes from, in words
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    kinds: tuple[str, ...]
    L: sp.csr_matrix
    Ld: sp.csr_matrix
    weighting: tuple[str, ...]
    recorded: IntArray
    pseudo: IntArray
    result_z: IntArray
    ratios: tuple[tuple[int, int, int], ...]
    sperling: tuple[tuple[int, int, str, float], ...]
    derivative: tuple[str, ...]

    @property
    def n_z(self) -> int:
        return int(self.L.shape[0])

    @property
    def direct(self) -> IntArray:
        """Result channels that are a z row (channels, linear and weighted derived channels)."""
        return np.flatnonzero(self.result_z >= 0)

    def derivative_sources(self) -> dict[str, str]:
        """Channel -> where its time derivative comes from (for provenance)."""
        return dict(zip(self.names, self.derivative))


def reduction_plan(output_names: Sequence[str], selected: Sequence[tuple[str, str]],
                   derived: Sequence[DerivedChannel], *, recorded_derivatives: bool = True) -> ReductionPlan:
    """The plan for an engine whose outputs are ``output_names``; ``selected`` = (name, unit) of the
    selected channels (the first outputs), ``derived`` the selected derived channels.
    ``recorded_derivatives=False`` takes the pseudo-derivative everywhere (to measure its error)."""
    col = {n: i for i, n in enumerate(output_names)}
    rows: list[tuple[tuple[tuple[str, float], ...], str]] = []
    index: dict[tuple[tuple[tuple[str, float], ...], str], int] = {}
    needs_d: set[int] = set()

    def z_of(terms: tuple[tuple[str, float], ...], weighting: str = "", derivative: bool = True) -> int:
        key = (tuple(sorted(terms)), weighting)
        if key not in index:
            index[key] = len(rows)
            rows.append(key)
        if derivative:
            needs_d.add(index[key])
        return index[key]

    names, units, kinds, result_z, ratios, sper = [], [], [], [], [], []
    for name, unit in selected:
        names.append(name), units.append(unit), kinds.append("channel")
        result_z.append(z_of(((name, 1.0),)))
    for d in derived:
        k = len(names)
        names.append(d.name), units.append(d.unit), kinds.append(d.kind)
        if d.kind == "linear":
            result_z.append(z_of(d.terms))
        elif d.kind == "weighted":
            result_z.append(z_of(d.terms, d.weighting))
        elif d.kind == "ratio":
            result_z.append(-1)
            ratios.append((k, z_of(d.terms), z_of(d.denominator)))
        elif d.kind == "sperling":
            result_z.append(-1)
            sper.append((k, z_of(d.terms, derivative=False), d.weighting, d.window))
        else:  # pragma: no cover - DerivedChannel's Literal
            raise ValueError(f"unknown derived kind {d.kind!r}")
    n_out = len(output_names)
    L = sp.lil_matrix((len(rows), n_out))
    Ld = sp.lil_matrix((len(rows), n_out))
    recorded, pseudo = [], []
    for z, (terms, _) in enumerate(rows):
        for name, c in terms:
            L[z, col[name]] += c
        if z not in needs_d:
            continue
        dnames = [derivative_name(n) for n, _ in terms]
        if recorded_derivatives and all(dn is not None and dn in col for dn in dnames):
            for (name, c), dn in zip(terms, dnames):
                Ld[z, col[dn]] += c  # type: ignore[index]
            recorded.append(z)
        else:
            pseudo.append(z)
    rec_set = set(recorded)
    words = []
    for k, z in enumerate(result_z):
        if z >= 0:
            terms = rows[z][0]
            if z in rec_set:
                words.append("recorded: " + " + ".join(f"{c:g} {derivative_name(n)}" for n, c in terms))
            else:
                words.append("pseudo-derivative (demodulated second-order differences)")
        elif kinds[k] == "ratio":
            _, zn, zd = next(r for r in ratios if r[0] == k)
            parts = ["recorded" if z_ in rec_set else "pseudo" for z_ in (zn, zd)]
            words.append(f"first order from N, D and their derivatives (N: {parts[0]}, D: {parts[1]})")
        else:
            words.append("none (a windowed index)")
    return ReductionPlan(
        names=tuple(names), units=tuple(units), kinds=tuple(kinds), L=L.tocsr(), Ld=Ld.tocsr(),
        weighting=tuple(w for _, w in rows), recorded=np.array(recorded, dtype=np.int64),
        pseudo=np.array(pseudo, dtype=np.int64), result_z=np.array(result_z, dtype=np.int64),
        ratios=tuple(ratios), sperling=tuple(sper), derivative=tuple(words),
    )


def engine_plan(engine: Any) -> ReductionPlan:
    """The plan of an engine's outputs and its model's selection (cached on the engine)."""
    plan = getattr(engine, "_reduction_plan", None)
    if plan is None:
        plan = reduction_plan(engine.outputs.names, list(engine.selected), engine.derived)
        engine._reduction_plan = plan
    return plan


def model_plan(model: Any, wheel_forces: bool = False) -> ReductionPlan:
    """The plan of a built model's engine outputs (the same as :func:`engine_plan` of an engine of it)."""
    names = [c.name for c in model.output_channels(wheel_forces)]
    return reduction_plan(names, [(c.name, c.unit) for c in model.selected], model.derived)


# ============================================================================================ the mean
@dataclass(frozen=True, eq=False)
class MeanRows:
    """The mean run's internal rows: values and time derivatives (n_z, n_t)."""

    value: FloatArray
    rate: FloatArray


def mean_rows(plan: ReductionPlan, outputs: FloatArray, time: FloatArray) -> MeanRows:
    """z rows of the mean run (its ``outputs``, (n_outputs, n_t)) and their time derivatives: the
    recorded derivative where the plan has one, else numpy.gradient; weighted rows filtered in time."""
    fs = 1.0 / float(time[1] - time[0])
    value = np.asarray(plan.L @ outputs)
    rate = np.gradient(value, time, axis=1) if time.size > 1 else np.zeros_like(value)
    if plan.recorded.size:
        rate[plan.recorded] = np.asarray(plan.Ld @ outputs)[plan.recorded]
    for z, w in enumerate(plan.weighting):
        if w:
            value[z] = apply_weighting(value[z], fs, w)  # type: ignore[arg-type]
            rate[z] = np.gradient(value[z], time)
    return MeanRows(value, rate)


@dataclass(frozen=True, eq=False)
class RatioCoefficients:
    """First-order coefficients of every ratio r = N / D about the means (each (n_ratio, n_t)):
    r~ = a N~ + b D~ and r~' = a N~' + b D~' + a_rate N~ + b_rate D~ (module docstring)."""

    a: FloatArray
    b: FloatArray
    a_rate: FloatArray
    b_rate: FloatArray
    mean: FloatArray
    mean_rate: FloatArray


def ratio_coefficients(plan: ReductionPlan, rows: MeanRows) -> RatioCoefficients:
    """a = 1/D, b = -N/D^2 and their time derivatives, with the ratio's mean N/D and its rate (first order)."""
    zn = np.array([r[1] for r in plan.ratios], dtype=np.int64)
    zd = np.array([r[2] for r in plan.ratios], dtype=np.int64)
    N, D = rows.value[zn], rows.value[zd]
    Nd, Dd = rows.rate[zn], rows.rate[zd]
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / D
        b = -N / D**2
        a_rate = -Dd / D**2
        b_rate = -Nd / D**2 + 2.0 * N * Dd / D**3
        mean = N / D
        mean_rate = Nd / D - N * Dd / D**2
    return RatioCoefficients(a, b, a_rate, b_rate, mean, mean_rate)


# ============================================================================================ PEM
def finish_pem_task(raw: dict[str, np.ndarray], plan: ReductionPlan, coef: RatioCoefficients | None,
                    psd_rows: Sequence[int] | None = None) -> dict[str, np.ndarray]:
    """A task's raw sums (:class:`PseudoReduction`) as per result channel arrays (n_res rows; Sperling
    rows zero): "var_t" (n_t, n_types, n_res), "dvar", "dcov", "lam" ((n_t, n_res), (n_t, n_res),
    (n_t, 2, n_res)), "psd" (len(psd_rows), n_freq, n_t) when kept: the result rows ``psd_rows``
    (None: all n_res), in that order, and "sperling_power" (n_t, n_sp).
    ``coef``: the ratios' first-order coefficients (:func:`ratio_coefficients`; None without ratios)."""
    var_z, lam_z = raw["var_z"], raw["lam_z"]
    n_t, n_types, _ = var_z.shape
    n_res = len(plan.names)
    direct = plan.direct
    zr = plan.result_z[direct]
    pos = {int(z): j for j, z in enumerate(np.concatenate((plan.recorded, plan.pseudo)))}
    var = np.zeros((n_t, n_types, n_res))
    lam = np.zeros((n_t, 2, n_res))
    dvar = np.zeros((n_t, n_res))
    dcov = np.zeros((n_t, n_res))
    var[:, :, direct] = var_z[:, :, zr]
    lam[:, :, direct] = lam_z[:, :, zr]
    jd = np.array([pos[int(z)] for z in zr], dtype=np.int64)
    if jd.size:
        dvar[:, direct] = raw["dvar_z"][:, jd]
        dcov[:, direct] = raw["dcov_z"][:, jd]
    psd = None
    at_row = {int(r): i for i, r in enumerate(range(n_res) if psd_rows is None else psd_rows)}
    if "psd_z" in raw:
        psd = np.zeros((len(at_row),) + raw["psd_z"].shape[1:], dtype=PSD_TRANSPORT)
        z_rows = raw.get("psd_z_rows", np.arange(raw["psd_z"].shape[0]))
        at_z = {int(z): k for k, z in enumerate(z_rows)}  # z row -> its row of psd_z
        kept = [(at_row[int(r)], at_z[int(z)]) for r, z in zip(direct, zr) if int(r) in at_row]
        if kept:
            psd[[i for i, _ in kept]] = raw["psd_z"][[k for _, k in kept]]
    if plan.ratios:
        assert coef is not None
        a, b, ar, br = (x.T for x in (coef.a, coef.b, coef.a_rate, coef.b_rate))  # (n_t, n_ratio)
        idx = np.array([r[0] for r in plan.ratios], dtype=np.int64)
        zn = np.array([r[1] for r in plan.ratios], dtype=np.int64)
        zd = np.array([r[2] for r in plan.ratios], dtype=np.int64)
        NN, DD, ND = var_z[:, :, zn], var_z[:, :, zd], raw["nd_type"]
        var[:, :, idx] = a[:, None] ** 2 * NN + b[:, None] ** 2 * DD + 2 * (a * b)[:, None] * ND
        lam[:, :, idx] = (a[:, None] ** 2 * lam_z[:, :, zn] + b[:, None] ** 2 * lam_z[:, :, zd]
                          + 2 * (a * b)[:, None] * raw["nd_lam"])
        jn = np.array([pos[int(z)] for z in zn], dtype=np.int64)
        jdd = np.array([pos[int(z)] for z in zd], dtype=np.int64)
        s_nn, s_dd, s_nd = NN.sum(axis=1), DD.sum(axis=1), ND.sum(axis=1)
        s_nn1, s_dd1 = raw["dcov_z"][:, jn], raw["dcov_z"][:, jdd]  # (N, N'), (D, D')
        s_n1n1, s_d1d1 = raw["dvar_z"][:, jn], raw["dvar_z"][:, jdd]
        s_nd1, s_dn1, s_n1d1 = (raw["nd_pairs"][:, k] for k in range(3))
        # r = a N + b D, r' = a N' + b D' + ar N + br D: quadratic forms of the covariances of (N, D, N', D')
        dvar[:, idx] = (ar**2 * s_nn + br**2 * s_dd + a**2 * s_n1n1 + b**2 * s_d1d1
                        + 2 * (ar * br * s_nd + ar * a * s_nn1 + ar * b * s_nd1 + br * a * s_dn1 + br * b * s_dd1
                               + a * b * s_n1d1))
        dcov[:, idx] = (a * a * s_nn1 + a * b * s_nd1 + a * ar * s_nn + a * br * s_nd
                        + b * a * s_dn1 + b * b * s_dd1 + b * ar * s_nd + b * br * s_dd)
        if psd is not None and "nd_psd" in raw:
            for k in (k for k, r in enumerate(idx) if int(r) in at_row):  # one ratio row at a time: no temporaries
                at, bt = coef.a[k][None, :], coef.b[k][None, :]  # (1, n_t)
                psd[at_row[int(idx[k])]] = (at**2 * raw["psd_z"][at_z[int(zn[k])]] + bt**2 * raw["psd_z"][at_z[int(zd[k])]]
                                            + 2 * at * bt * raw["nd_psd"][k])
    out = {"var_t": var, "lam": lam, "dvar": dvar, "dcov": dcov, "sperling_power": raw["sperling_power"]}
    if psd is not None:
        out["psd"] = psd
    return out


@dataclass(frozen=True, eq=False)
class PemStatistics:
    """Per result channel (n_res, n_t): mean, its rate, sigma, sigma of the derivative, the correlation
    rho of y and y', Vanmarcke's bandwidth delta (0 for Sperling channels, whose mean is the index)."""

    mean: FloatArray
    mean_rate: FloatArray
    std: FloatArray
    std_rate: FloatArray
    rho: FloatArray
    bandwidth: FloatArray


def finish_pem(plan: ReductionPlan, mean: FloatArray, time: FloatArray, rows: MeanRows,
               coef: RatioCoefficients | None, var: FloatArray, dvar: FloatArray, dcov: FloatArray,
               lam: FloatArray, sperling_power: FloatArray) -> PemStatistics:
    """The statistics of a PEM result from the sums over all tasks (:func:`finish_pem_task`'s, added):
    ``mean`` (n_res, n_t) the mean task's channels, ``var`` (n_res, n_t) sigma^2 summed over types,
    ``dvar``, ``dcov`` (n_t, n_res), ``lam`` (n_t, 2, n_res), ``sperling_power`` (n_t, n_sp).

    Sperling channels: Wz per window of the total acceleration's expected energy, the mean run's
    periodogram energy plus the random part's B-weighted power averaged over the window."""
    mean = np.array(mean, dtype=float)
    std = np.sqrt(np.maximum(var, 0.0))
    std_rate = np.sqrt(np.maximum(dvar.T, 0.0))
    denom = std * std_rate
    rho = np.clip(np.divide(dcov.T, denom, out=np.zeros_like(denom), where=denom > 0), -1.0, 1.0)
    bandwidth = bandwidth_from_moments(var, lam[:, 0].T, lam[:, 1].T)
    mean_rate = np.zeros_like(mean)
    direct = plan.direct
    mean_rate[direct] = rows.rate[plan.result_z[direct]]
    if plan.ratios:
        assert coef is not None
        idx = np.array([r[0] for r in plan.ratios], dtype=np.int64)
        mean_rate[idx] = coef.mean_rate
    fs = 1.0 / float(time[1] - time[0])
    for j, (k, z, direction, window) in enumerate(plan.sperling):
        slices, _, energy = sperling_window_energy(rows.value[z], fs, direction, window=window)  # type: ignore[arg-type]
        random = np.array([sperling_power[s, j].mean() for s in slices])
        mean[k] = window_series(sperling_index(energy + random), time.size, fs, window)
        std[k] = std_rate[k] = rho[k] = bandwidth[k] = mean_rate[k] = 0.0
    return PemStatistics(mean, mean_rate, std, std_rate, rho, bandwidth)


# ============================================================================================ Monte Carlo
def sample_offsets(plan: ReductionPlan, mean: FloatArray) -> FloatArray:
    """What Monte Carlo's sample moments are taken about: the mean run's channels (n_res, n_t), with the
    Sperling rows 0 (a sample's index is formed from its total acceleration)."""
    out = np.array(mean, dtype=float)
    for k, *_ in plan.sperling:
        out[k] = 0.0
    return out


class SampleReduction:
    """Monte Carlo's reduction of a task's samples (module docstring), a
    :class:`~tb_exudyn.engines.protocols.Reducer`: per output time the mean and
    the sum of squared deviations (from ``offsets``) of every result channel, per sample its minimum and
    maximum over the record and its smallest vertical wheel force, and, if asked, the samples.

    offsets : (n_res, n_t) the mean run's value of each channel (Sperling rows 0), or None (the full
        model: samples are totals); zmean : the mean run's z rows (n_z, n_t), or None; fs : output rate
    [Hz]; force_mean : (n_forces, n_t) the mean run's vertical wheel forces (outputs ``force_rows``), or
    None: every sample's minimum wheel force over the record is kept (the loss-of-contact guard)
    """

    def __init__(self, plan: ReductionPlan, force_rows: IntArray, n_t: int, n_samples: int, keep_samples: bool,
                 offsets: FloatArray | None, zmean: FloatArray | None, fs: float,
                 force_mean: FloatArray | None = None) -> None:
        self.plan, self.n, self.n_t, self.fs = plan, n_samples, n_t, float(fs)
        n_res = len(plan.names)
        self.offsets = np.zeros((n_res, n_t)) if offsets is None else np.asarray(offsets, dtype=float)
        self.zmean = np.zeros((plan.n_z, n_t)) if zmean is None else np.asarray(zmean, dtype=float)
        self.force_rows = force_rows
        self.mean, self.m2 = np.zeros((n_res, n_t)), np.zeros((n_res, n_t))
        self.lo = np.full((n_samples, n_res), np.inf)
        self.hi = np.full((n_samples, n_res), -np.inf)
        self.force_mean = np.zeros((force_rows.size, n_t)) if force_mean is None else np.asarray(force_mean, dtype=float)
        self.min_force = np.full(n_samples, np.inf if force_rows.size else np.nan)
        self.samples = np.zeros((n_samples, n_res, n_t)) if keep_samples else None
        weighted = [k for k in plan.direct if plan.weighting[plan.result_z[k]]]
        self.now = np.array([k for k in plan.direct if k not in set(weighted)], dtype=np.int64)  # formed per time
        self.now_z = plan.result_z[self.now]
        self.weighted = np.array(weighted, dtype=np.int64)
        hist = sorted({int(plan.result_z[k]) for k in weighted} | {s[1] for s in plan.sperling})
        self.hist_rows = np.array(hist, dtype=np.int64)
        self.hist_pos = {z: j for j, z in enumerate(hist)}
        self.hist = np.zeros((len(hist), n_samples, n_t))
        self.ratio_idx = np.array([r[0] for r in plan.ratios], dtype=np.int64)
        self.ratio_n = np.array([r[1] for r in plan.ratios], dtype=np.int64)
        self.ratio_d = np.array([r[2] for r in plan.ratios], dtype=np.int64)

    def _moments(self, rows: IntArray, i: int | slice, dev: FloatArray, total: FloatArray) -> None:
        """dev, total: (rows, n) at one time, or (rows, n, n_t) for a slice of all times."""
        mu = dev.mean(axis=1)
        d = dev - mu[:, None]
        self.mean[rows, i] = mu
        self.m2[rows, i] = np.einsum("ij...,ij...->i...", d, d)
        with np.errstate(invalid="ignore"):
            lo = total.min(axis=2) if total.ndim == 3 else total
            hi = total.max(axis=2) if total.ndim == 3 else total
        self.lo[:, rows] = np.fmin(self.lo[:, rows], lo.T)
        self.hi[:, rows] = np.fmax(self.hi[:, rows], hi.T)
        if self.samples is not None:
            if dev.ndim == 3:
                self.samples[:, rows, :] = dev.transpose(1, 0, 2)
            else:
                self.samples[:, rows, i] = dev.T

    def record(self, i: int, Y: ComplexArray, ext: IntArray) -> None:
        Yx = Y.view(np.float64)[ext][:, : self.n]  # (n_outputs, n) the samples, outputs in map order
        Z = np.asarray(self.plan.L @ Yx)
        if self.now.size:
            dev = Z[self.now_z]
            self._moments(self.now, i, dev, dev + self.offsets[self.now, i][:, None])
        if self.ratio_idx.size:
            r = (Z[self.ratio_n] + self.zmean[self.ratio_n, i][:, None]) / (Z[self.ratio_d] + self.zmean[self.ratio_d, i][:, None])
            self._moments(self.ratio_idx, i, r - self.offsets[self.ratio_idx, i][:, None], r)
        if self.hist_rows.size:
            self.hist[:, :, i] = Z[self.hist_rows]
        if self.force_rows.size:
            f = Yx[self.force_rows] + self.force_mean[:, i][:, None]
            np.minimum(self.min_force, f.min(axis=0), out=self.min_force)

    def result(self) -> dict[str, np.ndarray]:
        plan = self.plan
        for k in self.weighted:
            z = int(plan.result_z[k])
            dev = apply_weighting(self.hist[self.hist_pos[z]], self.fs, plan.weighting[z], axis=-1)  # type: ignore[arg-type]
            rows = np.array([k])
            self._moments(rows, slice(None), dev[None], (dev + self.offsets[k])[None])
        for k, z, direction, window in plan.sperling:
            acc = self.hist[self.hist_pos[z]] + self.zmean[z]
            _, _, energy = sperling_window_energy(acc, self.fs, direction, window=window)  # type: ignore[arg-type]
            series = window_series(sperling_index(energy), self.n_t, self.fs, window)  # (n, n_t)
            rows = np.array([k])
            self._moments(rows, slice(None), series[None] - self.offsets[k], series[None])
        out = {"n": np.array(self.n), "mean": self.mean, "m2": self.m2, "min_force": self.min_force,
               "sample_min": self.lo, "sample_max": self.hi}
        if self.samples is not None:
            out["samples"] = self.samples
        return out


__all__ = ["MeanRows", "PemStatistics", "REDUCTION_FORMAT", "PseudoReduction", "RatioCoefficients", "ReductionPlan", "SampleReduction", "engine_plan",
           "finish_pem", "finish_pem_task", "mean_rows", "model_plan", "ratio_coefficients", "reduction_plan"]
