"""Monte Carlo of the linear model: sampled irregularities as columns of the batched engine.

The samples of :func:`~.monte_carlo.run_monte_carlo` (the same ``ProfileSampler``, the same
``sample_rng(seed, k)``, so sample k has the very profile the Exudyn run of sample k has) are
integrated together, as real columns, by the batched engine's generalized-alpha integrator
(:func:`~.batched.integrate`) on the linear model (:mod:`.batched_model`: M, K0, D0 from Exudyn's
``ComputeLinearizedSystem`` about the rest state, the linear wheel-rail contact of the coupling).
Each sample is then Exudyn's deterministic run (gravity, static start, no irregularity: the mean
task, as in the batched PEM engine) plus the linear model's response to the sample's profiles from
rest. The method is labelled ``"monte_carlo_linear"``: what it leaves out is exactly what the
Exudyn model has beyond the linear one (the rigid bodies' large-rotation terms, about 1e-6 of the
responses for track irregularities), which PEM leaves out too. So it is a fast, independent check
of PEM's statistics (time-domain superposition of sampled profiles instead of pseudo-excitations),
not of the linearisation; the Exudyn Monte Carlo (``engine="exudyn"``) checks that.

Columns: two real samples per complex column (sample 2j as the real part, 2j + 1 as the imaginary
part), so the engine's complex machinery runs unchanged and its float64 view holds the samples in
order. Every component of the model integrates every column (a sample carries every kind of
irregularity), each with the full input of its contact rows.

Inputs: each sample's profiles are the cubic splines of the Exudyn Monte Carlo (not-a-knot, on the
sampler's grid), held as values and knot slopes (cubic Hermite form: the same cubic pieces) and
evaluated at every axle at every step; r = w p, r' = v (w' p + w p') with the approach taper w, as
``rail_inputs`` does. Memory per sample: 2 x (grid points) x (kinds) x 8 bytes (0.8 MB for the
reference study); tasks hold at most ``TASK_PROFILE_BYTES`` of profiles.

Reduction: at every output time a task reduces its samples to their mean and sum of squared
deviations (exact two-pass within the task); the parent merges tasks in task order (Chan et al.'s
pairwise update), so a result is bitwise the same for any number of workers, any executor and after
a resume. The vertical wheel forces (every ``*.force_z``, selected or not) of each sample go back
to the parent for the loss-of-contact check (minimum over the output times, as the Exudyn Monte
Carlo does).
"""

from __future__ import annotations

import json
import math
import os
import time as _time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from ..system.excitation import KINDS
from ..results.random_response import RandomResponse
from ..scenario import Scenario
from .batched import BatchedModel, MeanTask, _mean, _Run, _Step, check_linearization, default_slices, integrate
from .monte_carlo import (
    STATISTICS_PROVENANCE,
    Discretisation,
    ProfileSampler,
    contact_provenance,
    prepare_monte_carlo,
    sample_statistics,
    warn_loss_of_contact,
)
from .tasks import Task, run_tasks
from .threads import single_threaded_blas

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
#: largest profile storage (values and knot slopes of every kind) of one task's samples
TASK_PROFILE_BYTES = 192 * 2**20
#: columns of samples whose knot slopes are computed at once (bounds CubicSpline's temporaries)
SPLINE_CHUNK = 32
METHOD = "monte_carlo_linear"
LINEARIZED_ABOUT = {"rest": "rest (unloaded, as PEM)",
                    "static": "the static equilibrium under gravity (with the suspension preload's stiffness)"}


# ======================================================================================= columns
class SampleColumns:
    """Sampled irregularity profiles as the batched engine's columns (the column-source interface of
    :func:`~.batched.integrate`): complex column j holds sample 2j (real part) and 2j + 1 (imaginary
    part); an odd count is padded with a zero sample.

    Parameters
    ----------
    sampler : the scenario's ProfileSampler (the Exudyn Monte Carlo's)
    seed, indices : the run's seed and the samples' indices
    half_gauge : b [m], for a cross-level sampled as a height difference
    """

    def __init__(self, sampler: ProfileSampler, seed: int, indices: Sequence[int], half_gauge: float) -> None:
        grids = sampler.grids_batch(seed, indices)
        self.n_samples = len(indices)
        self.width = (self.n_samples + 1) // 2
        self.kind_index = np.array([KINDS.index(k) for k in KINDS if k in grids], dtype=np.int64)
        #: factor to the coupling's units (cross-level angle), as ``rail_inputs`` applies
        self.kind_scale = np.array([1.0 / (2.0 * half_gauge) if KINDS[k] == "cross_level"
                                    and sampler.cross_level_unit == "height" else 1.0 for k in self.kind_index])
        self.x_start, self.dx, self.n_points = sampler.x_start, sampler.dx, sampler.n_points
        shape = (self.n_points, self.kind_index.size, 2 * self.width)
        self.values, self.slopes = np.zeros(shape), np.zeros(shape)
        x = self.x_start + self.dx * np.arange(self.n_points)  # the grid of the Exudyn runs' splines
        for j, k in enumerate(self.kind_index):
            v = grids[KINDS[k]]
            self.values[:, j, : self.n_samples] = v
            for c0 in range(0, self.n_samples, SPLINE_CHUNK):
                c1 = min(c0 + SPLINE_CHUNK, self.n_samples)
                c = CubicSpline(x, v[:, c0:c1], axis=0).c  # (4, n - 1, chunk): powers 3, 2, 1, 0
                self.slopes[:-1, j, c0:c1] = c[2]
                self.slopes[-1, j, c0:c1] = (3.0 * c[0, -1] * self.dx + 2.0 * c[1, -1]) * self.dx + c[2, -1]

    @staticmethod
    def profile_bytes(sampler: ProfileSampler) -> int:
        """Bytes of profile storage per sample."""
        kinds = {kind for kind, _ in sampler.kinds}
        return 2 * sampler.n_points * len(kinds) * 8

    def columns_for(self, kinds: Sequence[int]) -> IntArray:
        """Every column, for a component that some sampled kind excites."""
        if np.isin(self.kind_index, kinds).any():
            return np.arange(self.width, dtype=np.int64)
        return np.zeros(0, dtype=np.int64)

    def at(self, step: _Step, speed: float) -> tuple[FloatArray, FloatArray] | None:
        """Profile values and slopes (n_axles, kinds, 2 width) at the axles (None: all inputs zero)."""
        if step.zero:
            return None
        s = (step.x - self.x_start) / self.dx
        if s.min() < -1e-9 or s.max() > self.n_points - 1 + 1e-9:
            raise ValueError(f"axles at x in [{step.x.min():g}, {step.x.max():g}] m outside the sampled track")
        i = np.clip(s.astype(np.intp), 0, self.n_points - 2)
        t = (s - i)[:, None, None]
        y0, y1, d0, d1 = self.values[i], self.values[i + 1], self.slopes[i], self.slopes[i + 1]
        t2 = t * t
        t3 = t2 * t
        dy = y1 - y0
        value = y0 + (3.0 * t2 - 2.0 * t3) * dy + self.dx * ((t3 - 2.0 * t2 + t) * d0 + (t3 - t2) * d1)
        slope = (6.0 * (t - t2) / self.dx) * dy + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (3.0 * t2 - 2.0 * t) * d1
        return value, slope

    def run_inputs(self, run: _Run, cols: IntArray, coupling) -> "_ProfileInputs":  # noqa: ANN001
        return _ProfileInputs(run, self, coupling)


class _ProfileInputs:
    """k r + c r' of a run's contact rows for sample columns: with P = W p and P' = W p' at the rows'
    axles (W the coupling's input map), k r + c r' = (k w + c v w') P + c v w P'."""

    def __init__(self, run: _Run, source: SampleColumns, coupling) -> None:  # noqa: ANN001
        W = coupling.contacts.input_map[np.ix_(run.rows, source.kind_index)] * source.kind_scale[None, :]
        self.terms = [(j, np.ascontiguousarray(W[:, j:j + 1])) for j in range(W.shape[1]) if np.any(W[:, j])]
        self.axle = run.axle
        self.k, self.cv = run.k[:, 0], run.c[:, 0] * coupling.speed
        n = 2 * source.width
        self.P, self.Pd, self.tmp = np.zeros((run.rows.size, n)), np.zeros((run.rows.size, n)), np.zeros((run.rows.size, n))

    def __call__(self, step: _Step, shared: tuple[FloatArray, FloatArray], out: NDArray[np.complex128]) -> None:
        value, slope = shared
        P, Pd, tmp = self.P, self.Pd, self.tmp
        P.fill(0.0)
        Pd.fill(0.0)
        for j, wj in self.terms:
            np.multiply(wj, value[self.axle, j], out=tmp)
            P += tmp
            np.multiply(wj, slope[self.axle, j], out=tmp)
            Pd += tmp
        w, dw = step.w[self.axle], step.dw[self.axle]
        of = out.view(np.float64)
        np.multiply((self.k * w + self.cv * dw)[:, None], P, out=of)
        np.multiply((self.cv * w)[:, None], Pd, out=tmp)
        of += tmp


# ===================================================================================== reduction
class SampleReducer:
    """At every output time: the mean and the sum of squared deviations of the task's samples over
    the scenario's channels, the samples' vertical wheel forces and, if asked, the samples."""

    def __init__(self, bm: BatchedModel, n_samples: int, keep_samples: bool) -> None:
        n_t, n_sel = bm.output_time.size, bm.n_selected
        names = bm.channels.names
        self.n_sel, self.n = n_sel, n_samples
        self.force_rows = np.array([names.index(c.name) for c in bm.force_channels], dtype=np.int64)
        self.mean, self.m2 = np.zeros((n_sel, n_t)), np.zeros((n_sel, n_t))
        self.force = np.zeros((self.force_rows.size, n_t, n_samples))
        self.samples = np.zeros((n_samples, n_sel, n_t)) if keep_samples else None

    def record(self, i: int, Y: NDArray[np.complex128], ext: IntArray) -> None:
        Yx = Y.view(np.float64)[ext]  # (n_ch, 2 width): the samples in order, channels in map order
        ys = Yx[: self.n_sel, : self.n]
        mu = ys.mean(axis=1)
        d = ys - mu[:, None]
        self.mean[:, i] = mu
        self.m2[:, i] = np.einsum("ij,ij->i", d, d)
        self.force[:, i, :] = Yx[self.force_rows, : self.n]
        if self.samples is not None:
            self.samples[:, :, i] = ys.T

    def result(self) -> dict[str, np.ndarray]:
        out = {"n": np.array(self.n), "mean": self.mean, "m2": self.m2, "force": self.force}
        if self.samples is not None:
            out["samples"] = self.samples
        return out


def integrate_samples(bm: BatchedModel, sampler: ProfileSampler, seed: int, indices: Sequence[int],
                      keep_samples: bool = False) -> dict[str, np.ndarray]:
    """The linear model's responses to samples ``indices`` (from rest, no gravity), reduced at every
    output time by :class:`SampleReducer`."""
    with single_threaded_blas():
        columns = SampleColumns(sampler, seed, indices, bm.lin.coupling.half_gauge)
        return integrate(bm, columns, SampleReducer(bm, len(indices), keep_samples))


# ======================================================================================== driver
@dataclass(frozen=True)
class SampleTask:
    """Samples [start, stop) of a run seeded with ``seed``."""

    seed: int
    start: int
    stop: int
    keep_samples: bool


def _setup(scenario: Scenario, discretisation: Discretisation, linearization: str = "rest"
           ) -> tuple[BatchedModel, ProfileSampler]:
    return BatchedModel(scenario, wheel_forces=True, linearization=linearization), ProfileSampler(scenario, discretisation)


def _work(state: tuple[BatchedModel, ProfileSampler], task: Task) -> dict[str, np.ndarray]:
    bm, sampler = state
    if isinstance(task.data, MeanTask):
        return _mean(bm)
    st: SampleTask = task.data
    return integrate_samples(bm, sampler, st.seed, range(st.start, st.stop), st.keep_samples)


def sample_blocks(n: int, weights: Sequence[float], largest: int) -> list[tuple[int, int]]:
    """Samples 0..n-1 cut into contiguous blocks in proportion to ``weights``, none above ``largest``."""
    w = np.asarray(weights, dtype=float)
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * n).astype(int))
    blocks = []
    for a, b in zip(edges[:-1], edges[1:]):
        pieces = -(-(b - a) // largest)
        cuts = np.round(np.linspace(a, b, pieces + 1)).astype(int)
        blocks += [(int(p), int(q)) for p, q in zip(cuts[:-1], cuts[1:]) if q > p]
    return blocks


def run_monte_carlo_linear(
    scenario: Scenario,
    n_samples: int | None = None,
    seed: int | None = None,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_samples: bool = False,
    discretisation: Discretisation = "pem_grid",
    slices: Sequence[float] | None = None,
    linearization: str = "rest",
) -> RandomResponse:
    """Monte Carlo of the linear model with the batched engine; arguments as
    :func:`~.monte_carlo.run_monte_carlo` (which calls this with ``engine="batched"``).

    Parameters
    ----------
    slices : relative sizes of the sample blocks (tasks; default one per core and a half one); a
        block holds at most ``TASK_PROFILE_BYTES`` of profiles. The result depends on the blocks only
        at round-off level, and the blocks not on ``workers`` or ``executor``.
    linearization : "rest" (default: PEM's model, also the Exudyn PEM engine's) or "static" (about the
        static equilibrium under gravity, with the suspensions' preload stiffness, as the Exudyn model
        with gravity has it: see :mod:`.batched_model`)

    Returns
    -------
    RandomResponse with method ``"monte_carlo_linear"``: the sample mean and standard deviation
    (ddof = 1) with their 95 % confidence intervals, ``min_wheel_force`` per sample and, if asked,
    the samples (N, n_ch, n_t). The samples are those of the Exudyn Monte Carlo with the same seed.

    Warns
    -----
    LossOfContactWarning when a sample's minimum vertical wheel-rail force is <= 0.
    """
    t0 = _time.perf_counter()
    check_linearization(linearization)
    identity = {"method": METHOD, "engine": "batched"} | ({} if linearization == "rest" else {"linearization": linearization})
    n, seed, sampler, out, checkpoint = prepare_monte_carlo(
        scenario, n_samples, seed, discretisation, out, resume, identity, "checkpoint-mc-linear")
    largest = max(2, TASK_PROFILE_BYTES // SampleColumns.profile_bytes(sampler))
    blocks = sample_blocks(n, default_slices(os.cpu_count() or 1) if slices is None else slices, largest)
    tasks = [Task("mcl-mean", MeanTask())]
    tasks += [Task(f"mcl-{a:07d}-{b - 1:07d}", SampleTask(seed, a, b, keep_samples)) for a, b in blocks]
    state: dict[str, Any] = {"n": 0, "check": 0.0}
    min_force = np.full(n, math.nan)
    samples: np.ndarray | None = None

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        nonlocal samples
        if isinstance(task.data, MeanTask):
            state["det"] = result
            for message in result["warnings"]:
                warnings.warn(str(message), stacklevel=4)
            return
        det = state["det"]
        st: SampleTask = task.data
        nb, mean_b, m2_b = int(result["n"]), result["mean"], result["m2"]
        if mean_b.shape != det["mean"].shape or nb != st.stop - st.start:
            raise RuntimeError(f"task {task.key}: {nb} samples of shape {mean_b.shape}, expected "
                               f"{st.stop - st.start} of {det['mean'].shape}")
        na = state["n"]
        if na == 0:
            state["mean"], state["m2"] = mean_b.copy(), m2_b.copy()
        else:  # Chan, Golub & LeVeque's pairwise update, in task order
            delta = mean_b - state["mean"]
            state["mean"] += delta * (nb / (na + nb))
            state["m2"] += m2_b + delta * delta * (na * nb / (na + nb))
        state["n"] = na + nb
        if det["force_mean"].shape[0]:
            min_force[st.start:st.stop] = (det["force_mean"][:, :, None] + result["force"]).min(axis=(0, 1))
        if keep_samples:
            if samples is None:
                samples = np.empty((n,) + det["mean"].shape)
            samples[st.start:st.stop] = det["mean"][None] + result["samples"]
        state["check"] = max(state["check"], float(np.max(result["contact_check"])))
        state["components"] = result["components"]
        state["alpha"] = result["alpha"]

    stats = run_tasks(
        tasks, setup=_setup, setup_args=(scenario, discretisation, linearization), work=_work, reduce=reduce, workers=workers,
        executor=executor, checkpoint=checkpoint, progress=progress, desc="Monte Carlo (linear, batched)",
    )
    det = state["det"]
    mean = det["mean"] + state["mean"]
    std, mean_ci, std_ci = sample_statistics(mean, state["m2"], n)
    lost = warn_loss_of_contact(min_force)
    provenance = {
        **json.loads(str(det["provenance"])),
        "engine": "batched",
        "mean_engine": "exudyn",
        "method": METHOD,
        "model": "linear: each sample is Exudyn's deterministic run (gravity, static start) plus the response of "
                 f"the model linearised about {LINEARIZED_ABOUT[linearization]} (M, K, D from Exudyn, the linear "
                 "wheel-rail contact) to the sample's profiles, integrated by the batched engine; the samples are "
                 "the Exudyn Monte Carlo's",
        "linearization": linearization,
        "seconds": _time.perf_counter() - t0,
        "mean_seconds": float(det["seconds"]),
        "seed": seed,
        "n_samples": n,
        "sample_blocks": [list(b) for b in blocks],
        "contact_check": state["check"],
        "components": [
            {"coordinates": int(c), "bridge_modes": int(b), "contacts": int(r),
             "kinds": [kind for j, kind in enumerate(KINDS) if mask >> j & 1]}
            for c, b, r, mask in state["components"]
        ],
        "generalized_alpha": dict(zip(("spectral_radius", "alpha_m", "alpha_f", "gamma", "beta", "time_step_s"),
                                      map(float, state["alpha"]))),
        **contact_provenance(min_force, lost),
        **STATISTICS_PROVENANCE,
        **sampler.describe(),
        **stats,
    }
    result = RandomResponse(
        method=METHOD, time=det["time"], channels=tuple(str(c) for c in det["names"]),
        units=tuple(str(u) for u in det["units"]), mean=mean, std=std,
        band=tuple(float(b) for b in sampler.band),  # type: ignore[arg-type]
        scenario=scenario.replace(analysis=scenario.analysis.replace(n_samples=n, seed=seed)),
        types=tuple(scenario.track.irregularities), std_ci=std_ci, mean_ci=mean_ci, n_samples=n,
        min_wheel_force=min_force, samples=samples, provenance=provenance,
    )
    if out is not None:
        result.save(Path(out) / "mc_linear")
    return result
