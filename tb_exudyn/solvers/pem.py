"""The pseudo-excitation method (PEM) on the Exudyn model: the frequency sweep.

For each irregularity spectrum S (one-sided, rad/m) and grid frequency f_k [Hz] with width df_k, the
pseudo-irregularity at wheel j is r~_j(t) = a_k exp(i Omega_k (v t - a_j)), Omega_k = 2 pi f_k / v,
a_k = sqrt(S(Omega_k) dOmega_k) = sqrt(S_hz(f_k) df_k). The system is linear in the irregularity, so
each pseudo-response is y~ = y_re + i y_im from two ordinary real runs (cosine and sine input, no
gravity), both at a fixed working amplitude A (Analysis.pem_amplitude) and scaled by a_k / A:
Exudyn's Newton was seen to stop early at amplitudes of 1e-6 m and below, and the rigid-body
nonlinearity is 5e-7 relative at 1e-5 m.

Then, with independent spectra adding,

    S_y(f_k, t) = sum over spectra |y~_k(t)|^2 / df_k         (one-sided PSD per Hz)
    sigma_y^2(t) = sum_k S_y(f_k, t) df_k                      (over the analysed band)

and the mean is the deterministic run (gravity, no irregularity). Frequencies whose wavelength
v / f lies outside the track's wavelength band carry no irregularity (PSD zero there).
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..results.random_response import RandomResponse
from ..results.storage import check_writable
from ..scenario import Scenario, ScenarioError, scenario_to_toml
from ..track import get_spectrum
from .grid import FrequencyGrid, band_mask, check_grid_against_spectra, scenario_grid
from .tasks import Checkpoint, Task, fingerprint, run_tasks

#: the engines of :func:`run_pem`: Exudyn runs (the reference) or the batched linear integrator
ENGINES: tuple[str, ...] = ("exudyn", "batched")


@dataclass(frozen=True)
class PemTask:
    """One (spectrum, frequency) pair: two runs (real and imaginary part)."""

    type_index: int
    spectrum: str
    freq_index: int
    f: float
    df: float
    amplitude: float  # a_k = sqrt(S_hz(f) df): the true pseudo-amplitude


def kind_and_unit(spectrum_name: str) -> tuple[str, str]:
    """The coupling's input kind for a spectrum and, for cross-level, whether it is an angle or a height."""
    s = get_spectrum(spectrum_name)
    if s.kind not in ("vertical", "alignment", "cross_level"):
        raise ScenarioError(
            None, "track.irregularities", spectrum_name,
            "vertical, alignment or cross-level spectra (gauge irregularity does not excite this model)",
            "irregularity kind not modelled",
        )
    return s.kind, ("height" if s.unit == "m" else "angle")


def pem_tasks(scenario: Scenario, grid: FrequencyGrid) -> list[Task]:
    """One task per (spectrum, frequency inside the wavelength band), in a fixed order."""
    mask = band_mask(grid, scenario)
    tasks = []
    for ti, name in enumerate(scenario.track.irregularities):
        s = get_spectrum(name)
        for k in np.flatnonzero(mask):
            omega, d_omega = grid.omega_spatial[k], grid.d_omega_spatial[k]
            amp = math.sqrt(float(s.psd(omega)) * d_omega)
            data = PemTask(ti, name, int(k), float(grid.f[k]), float(grid.df[k]), amp)
            tasks.append(Task(f"pem-{ti}-{k:05d}", data))
    return tasks


# ---------------------------------------------------------------------------------- worker side
def _setup(scenario: Scenario):
    """Build the Exudyn model once per worker (its warnings were shown by the deterministic run)."""
    from ..builder import build_model

    return build_model(scenario, warn=False)


def _work(model, task: Task) -> dict[str, np.ndarray]:
    """Real and imaginary pseudo-runs for one (spectrum, frequency); returns |y~|^2 per channel and time."""
    from ..system.excitation import HarmonicExcitation
    from .deterministic import run_model

    p: PemTask = task.data
    scenario = model.scenario
    kind, unit = kind_and_unit(p.spectrum)
    A = scenario.analysis.pem_amplitude
    omega = 2 * math.pi * p.f / scenario.speed
    parts = []
    for part in ("real", "imag"):
        excitation = HarmonicExcitation(kind=kind, spatial_frequency=omega, amplitude=A, part=part,
                                        cross_level_unit=unit)
        th, _ = run_model(model, excitation, gravity=False, initial="rest")
        parts.append(np.stack([th.channels[n] for n in th.names]))
    scale2 = (p.amplitude / A) ** 2
    return {"power": (parts[0] ** 2 + parts[1] ** 2) * scale2}


# ---------------------------------------------------------------------------------- driver
def prepare_sweep(scenario: Scenario, out: str | Path | None, resume: bool, identity: dict[str, Any]):
    """Checks shared by the PEM engines, before any run: irregularities present and modelled, the grid
    inside every spectrum's validity and the wavelength band, the output folder writable, and the
    checkpoint (whose fingerprint is ``identity`` plus the scenario). Returns grid, spectra, out, checkpoint."""
    if not scenario.track.irregularities:
        raise ScenarioError(None, "track.irregularities", [], "at least one spectrum name", "no irregularity to analyse")
    grid = scenario_grid(scenario)
    spectra = {n: get_spectrum(n) for n in scenario.track.irregularities}
    for n in spectra:
        kind_and_unit(n)
    check_grid_against_spectra(grid, scenario, spectra)
    checkpoint = None
    if out is not None:
        out = check_writable(out)
        fp = fingerprint({**identity, "scenario": scenario_to_toml(scenario)})
        checkpoint = Checkpoint(out / "checkpoint", fp, resume)
    elif resume:
        raise ScenarioError(None, "resume", True, "resume only together with an output folder", "nothing to resume from")
    return grid, spectra, out, checkpoint


def run_pem(
    scenario: Scenario,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_psd: bool = True,
    engine: str = "exudyn",
    linearization: str = "rest",
) -> RandomResponse:
    """Time-dependent PSD, sigma(t) and mean of every channel by the pseudo-excitation method.

    Parameters
    ----------
    scenario : the scenario (its track.irregularities are the independent spectra)
    workers : processes of the local pool (None: all cores; 1: in this process)
    executor : any ``concurrent.futures.Executor`` to use instead (e.g. a Dask client's executor)
    out : folder for checkpoints (``out/checkpoint``) and the result; checked writable before any run
    resume : skip tasks already finished in ``out/checkpoint``
    progress : show a progress bar with the time left
    keep_psd : keep the PSD map (channels x frequencies x output times); sigma is always kept
    engine : "exudyn" (two Exudyn runs per type and frequency: the reference) or "batched" (all
        pseudo-excitations in one integration of the same linear model with Exudyn's
        generalized-alpha step, :mod:`.batched`; the mean is Exudyn's run in both)
    linearization : "rest" (both engines: pseudo-runs from the unloaded rest state without gravity) or,
        with the batched engine only, "static" (about the static equilibrium under gravity, which adds
        the suspensions' preload stiffness that the Exudyn model with gravity, hence its Monte Carlo,
        has; see :mod:`.batched_model`)

    Returns
    -------
    RandomResponse with mean (deterministic run), std, psd [unit^2/Hz], band and provenance.
    """
    from .deterministic import run_deterministic

    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(repr(e) for e in ENGINES)}, got {engine!r}")
    if engine == "batched":
        from .batched import run_pem_batched

        return run_pem_batched(scenario, workers=workers, executor=executor, out=out, resume=resume,
                               progress=progress, keep_psd=keep_psd, linearization=linearization)
    if linearization != "rest":
        raise ScenarioError(None, "linearization", linearization, "'rest' with engine 'exudyn' ('static' needs "
                            "engine 'batched')", "the Exudyn engine's pseudo-runs start from rest without gravity")
    t0 = _time.perf_counter()
    grid, spectra, out, checkpoint = prepare_sweep(scenario, out, resume, {"method": "pem"})

    mean_th = run_deterministic(scenario)
    channels, nt = tuple(mean_th.names), mean_th.time.size
    units = tuple(mean_th.units[c] for c in channels)
    mean = np.stack([mean_th.channels[c] for c in channels])
    n_types = len(spectra)
    var_by_type = np.zeros((n_types, len(channels), nt))
    psd = np.zeros((len(channels), grid.f.size, nt)) if keep_psd else None
    tasks = pem_tasks(scenario, grid)

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        p: PemTask = task.data
        power = result["power"]
        if power.shape != (len(channels), nt):
            raise RuntimeError(f"task {task.key}: response shape {power.shape}, expected {(len(channels), nt)}")
        var_by_type[p.type_index] += power
        if psd is not None:
            psd[:, p.freq_index, :] += power / p.df

    stats = run_tasks(
        tasks, setup=_setup, setup_args=(scenario,), work=_work, reduce=reduce, workers=workers,
        executor=executor, checkpoint=checkpoint, progress=progress, desc="PEM",
    )
    std = np.sqrt(var_by_type.sum(axis=0))
    provenance = {
        **mean_th.provenance,
        "engine": "exudyn",
        "method": "pem",
        "seconds": _time.perf_counter() - t0,
        "pem_amplitude": scenario.analysis.pem_amplitude,
        "n_frequencies": int(grid.f.size),
        "n_frequencies_in_band": int(band_mask(grid, scenario).sum()),
        "quadrature": grid.rule,
        **stats,
    }
    result = RandomResponse(
        method="pem", time=mean_th.time, channels=channels, units=units, mean=mean, std=std,
        band=grid.band, scenario=scenario, freq=grid.f, df=grid.df, psd=psd, var_by_type=var_by_type,
        types=tuple(spectra), provenance=provenance,
    )
    if out is not None:
        result.save(out / "pem")
    return result
