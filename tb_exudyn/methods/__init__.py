"""Methods: what is computed (the mean run, PEM, Monte Carlo), on any engine, under any execution.

:func:`simulate` is the one entry point: ``simulate(scenario, "pem", engine="batched",
execution=Execution(workers=2, out="out"))``; :func:`run_pem`, :func:`run_monte_carlo` and
:func:`run_deterministic` are its thin, stable wrappers (the public API). Where a setting comes from:

- the scenario (TOML or dataclasses): every number of the physics and of the analysis (time step,
  grid, contact, gravity, linearization point, channels);
- the engine's options (``options``; e.g. the Exudyn engine's :class:`SolverSettings`): how an engine
  integrates, to within its stated tolerances;
- the method's options (``keep_psd``; ``n_samples``, ``seed``, ``keep_samples``, ``discretisation``);
- :class:`~tb_exudyn.execution.Execution`: how the tasks run (workers, executor, output folder,
  resume, progress, slices); it changes no number.

Every option that changes a number is in the checkpoint's fingerprint (with the package versions).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

from ..builder import build_model
from ..builder.system_modes import damping_guard, system_modes
from ..engines import DEFAULT_ENGINE, engine_class
from ..engines.batched import BatchedOptions
from ..engines.exudyn_runs import SolverSettings
from ..errors import CapabilityError, SettingError
from ..execution import Execution
from ..results.random_response import RandomResponse
from ..scenario import Scenario
from ..scenario.io import as_scenario
from ..system.linear import LINEARIZATIONS
from . import monte_carlo, pem, sweep, uq
from .deterministic import DeterministicMethod, run_deterministic, summarize
from .driver import Method, RunPlan, drive
from .monte_carlo import LossOfContactWarning, MonteCarloMethod
from .pem import PemMethod

#: method name -> its :class:`~.driver.Method` class, built as ``cls(scenario, engine, **method options)``
#: (the engine's options as ``options=``) and run by :func:`~.driver.drive`
METHODS: dict[str, Callable[..., Method]] = {
    "deterministic": DeterministicMethod,
    "pem": PemMethod,
    "monte_carlo": MonteCarloMethod,
}


def simulate(scenario: Scenario | str | Path, method: str, engine: str | None = None, execution: Execution | None = None,
             **options: Any) -> Any:
    """Run ``method`` ("deterministic", "pem" or "monte_carlo") on ``engine`` ("exudyn", "batched",
    "dense"; None: "exudyn" for the deterministic run, which is one Exudyn run, else
    :data:`~tb_exudyn.engines.DEFAULT_ENGINE`) under ``execution``; ``options`` are the method's (and
    ``options=`` the engine's). ``scenario``: a Scenario, or a scenario's name or file (loaded). The driver (:func:`~.driver.drive`) runs every method's skeleton."""
    if method not in METHODS:
        raise SettingError("simulate", "method", method, " or ".join(map(repr, METHODS)))
    if engine is None:
        engine = "exudyn" if method == "deterministic" else DEFAULT_ENGINE
    scenario = as_scenario(scenario, "simulate")
    return drive(METHODS[method](scenario, engine, **options), execution or Execution(where="simulate"))


def _with_linearization(scenario: Scenario, linearization: str | None, where: str) -> Scenario:
    if linearization is None or linearization == scenario.analysis.linearization:
        return scenario
    if linearization not in LINEARIZATIONS:
        raise SettingError(where, "linearization", linearization, " or ".join(map(repr, LINEARIZATIONS)),
                           "unknown linearization point")
    return scenario.replace(analysis=scenario.analysis.replace(linearization=linearization))


def run_pem(
    scenario: Scenario | str | Path,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_psd: bool = True,
    engine: str = DEFAULT_ENGINE,
    linearization: str | None = None,
    options: Any = None,
    slices: Any = None,
    grid_error: bool | str | None = None,
    psd_channels: Any = "key",
    overwrite: bool = False,
    keep_checkpoint: bool = False,
    max_memory: int | str | None = None,
    where: str = "run_pem",
) -> RandomResponse:
    """Time-dependent PSD, sigma(t) and mean of every channel by the pseudo-excitation method.

    Parameters
    ----------
    scenario : the scenario (its track.irregularities are the independent spectra), or a scenario's name
        or TOML file (loaded by :func:`~tb_exudyn.load_scenario`)
    workers : processes of the local pool (None: all cores; 1: in this process)
    executor : any ``concurrent.futures.Executor`` to use instead (e.g. a Dask client's executor)
    out : folder for checkpoints (``out/checkpoint``) and the result (``out/pem``); checked writable
        before any run
    resume : skip tasks already finished in ``out/checkpoint`` (each checkpoint file is checked first;
        one that fails is computed again, with a notice naming it)
    progress : show a progress bar with the time left
    keep_psd : keep PSD maps (channels x frequencies x output times, float32); sigma is always kept
    psd_channels : whose PSD maps to keep: "key" (default: the channels with code checks and those of
        the reference study's figures, a short list per component), "all", or glob patterns
    engine : "exudyn" (two Exudyn runs per type and frequency: the reference), "batched" (all
        pseudo-excitations in one integration of the same linear model with Exudyn's
        generalized-alpha step) or "dense" (the same on full matrices: a small reference); the mean
        is the engine's deterministic run (:class:`~.common.MeanTask`): Exudyn's on the Exudyn and the
        dense engine by default, the linear model's under the dead loads on the batched engine by
        default (``mean_engine`` in the provenance says which)
    linearization : overrides ``analysis.linearization``: "rest" (every engine: pseudo-runs from the
        unloaded rest state without gravity) or, with a linear engine, "static" (about the static
        equilibrium under gravity, with the suspensions' preload stiffness)
    options : the engine's options (the Exudyn engine: :class:`SolverSettings`)
    slices : relative task sizes of a linear engine (see :class:`~tb_exudyn.execution.Execution`)
    grid_error : estimate the frequency grid's error per channel from a sweep on the cell midpoints
        (None: with the engines that integrate all columns at once, where it is cheap); stored in
        ``provenance["grid_error"]`` and warned about above 1 % of a channel's max sigma; or the
        estimate's name: "local" (what True and None give: only the cells coarser than the adaptive
        grid's rules, :mod:`tb_exudyn.methods.grid_error`) or "midpoints" (every cell's midpoint)
    overwrite : replace the result and checkpoint of an earlier run in ``out`` (without it or
        ``resume``, a run into a folder holding them is refused: OutputFolderError); a folder another
        run is using is always refused
    keep_checkpoint : keep ``out/checkpoint`` after the result is saved (default: removed then)
    max_memory : the memory the run may use (bytes, or a text such as "4GB"; None: what this machine
        has available): a run estimated above it is refused before it starts (ResourceError giving the
        estimate and the key to change)
    where : the caller, named in messages (the ``tb-exudyn`` command passes its own); the keys are
        the arguments' names

    Returns
    -------
    RandomResponse with mean (deterministic run), std, psd [unit^2/Hz], band and provenance (the
    damping guard's and the grid's warnings in ``provenance["warnings"]``).
    """
    scenario = as_scenario(scenario, where)
    execution = Execution(workers=workers, executor=executor, out=out, resume=resume, progress=progress,
                          slices=slices, where=where, overwrite=overwrite, max_memory=max_memory,
                          keep_checkpoint=keep_checkpoint)
    return drive(PemMethod(_with_linearization(scenario, linearization, where), engine, options=options,
                           keep_psd=keep_psd, grid_error=grid_error, psd_channels=psd_channels), execution)


def run_monte_carlo(
    scenario: Scenario | str | Path,
    n_samples: int | None = None,
    seed: int | None = None,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_samples: bool = False,
    discretisation: str = "pem_grid",
    engine: str = DEFAULT_ENGINE,
    linearization: str | None = None,
    options: Any = None,
    slices: Any = None,
    overwrite: bool = False,
    keep_checkpoint: bool = False,
    max_memory: int | str | None = None,
    where: str = "run_monte_carlo",
) -> RandomResponse:
    """Sample mean and standard deviation of every channel over sampled irregularity profiles.

    Parameters
    ----------
    scenario : the scenario (its track.irregularities are sampled independently), or its name or file
    n_samples : number of samples N >= 2 (default ``scenario.analysis.n_samples``)
    seed : seed of the run (default ``scenario.analysis.seed``); sample k uses ``sample_rng(seed, k)``
    workers, executor, out, resume, progress : as :func:`run_pem` (checkpoints in
        ``out/checkpoint-mc`` or ``out/checkpoint-mc-linear``, results in ``out/mc`` or
        ``out/mc_linear``); the checkpoint does not depend on N, so a larger N with ``resume=True``
        reuses the samples already run
    keep_samples : keep every sample's channels, (N, nc, nt), in ``samples``
    discretisation : "pem_grid" (the PEM grid's discretised spectrum with random phases: comparable
        with PEM's sigma exactly), "pem_grid_gaussian" (the same spectrum with Gaussian coefficients:
        an exactly Gaussian process, for comparing exceedance probabilities with PEM's) or "fft" (FFT
        profiles over the wavelength band, for long tracks)
    engine : "exudyn" (one Exudyn run of the full model per sample: the reference, method
        "monte_carlo") or a linear engine ("batched", "dense": the same samples on the linear model,
        method "monte_carlo_linear")
    linearization : a linear engine's linearization point (overrides ``analysis.linearization``); the
        Exudyn engine runs the full model and takes none
    options, slices, overwrite, keep_checkpoint, max_memory, where : as :func:`run_pem`

    Returns
    -------
    RandomResponse with the sample mean, the sample standard deviation (ddof = 1), their 95 %
    confidence intervals ``mean_ci`` and ``std_ci``, ``min_wheel_force`` per sample and, if asked,
    the samples.

    Warns
    -----
    LossOfContactWarning when a sample's minimum vertical wheel-rail force is <= 0.
    """
    scenario = as_scenario(scenario, where)
    if linearization is not None and engine_class(engine, where).full_model:
        raise CapabilityError(where, "linearization", linearization,
                              "none with engine 'exudyn' (or a linear engine: 'batched', 'dense')",
                              "the Exudyn Monte Carlo runs the full model, it linearises nothing")
    execution = Execution(workers=workers, executor=executor, out=out, resume=resume, progress=progress,
                          slices=slices, where=where, overwrite=overwrite, max_memory=max_memory,
                          keep_checkpoint=keep_checkpoint)
    return drive(MonteCarloMethod(_with_linearization(scenario, linearization, where), engine, n_samples=n_samples,
                                  seed=seed, keep_samples=keep_samples, discretisation=discretisation,  # type: ignore[arg-type]
                                  options=options, where=where), execution)


__all__ = ["DEFAULT_ENGINE", "BatchedOptions", "DeterministicMethod", "Execution", "LossOfContactWarning", "METHODS",
           "Method", "MonteCarloMethod", "PemMethod", "RunPlan", "SolverSettings", "build_model", "damping_guard",
           "drive", "monte_carlo", "pem", "run_deterministic", "run_monte_carlo", "run_pem", "simulate", "summarize",
           "sweep", "system_modes"]
