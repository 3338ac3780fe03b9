"""The pseudo-excitation method (PEM): the frequency sweep, on any engine (a package: columns.py the
columns, tasks and slices; channels.py the checks and the kept PSD rows; sizing.py the memory
estimate; method.py :class:`PemMethod`, run by :func:`tb_exudyn.methods.driver.drive`).

For each irregularity spectrum S (one-sided, rad/m) and grid frequency f_k [Hz] with width df_k, the
pseudo-irregularity at wheel j is r~_j(t) = a_k exp(i Omega_k (v t - a_j)), Omega_k = 2 pi f_k / v,
a_k = sqrt(S(Omega_k) dOmega_k) = sqrt(S_hz(f_k) df_k): one complex column of
:class:`~tb_exudyn.system.columns.HarmonicColumns`. The system is linear in the irregularity, so the
engine integrates each column's response y~ (the Exudyn engine as two real runs, the linear engines
all columns at once), and with independent spectra adding

    S_y(f_k, t) = sum over spectra |y~_k(t)|^2 / df_k         (one-sided PSD per Hz)
    sigma_y^2(t) = sum_k S_y(f_k, t) df_k                      (over the analysed band)

(:class:`PsdReducer`); the mean is the deterministic run (gravity, no irregularity) as a task of its
own, by the engine: the batched engine's is the linear model's under the dead loads (Exudyn's
nonlinear run with ``BatchedOptions(mean="exudyn")``), the Exudyn engine's Exudyn's; the provenance's
``mean_engine`` says which. Frequencies whose wavelength v / f lies outside the track's wavelength band carry no
irregularity (PSD zero there).

Tasks: an engine that runs columns separately (``single_columns``) gets one task per column; the
others get slices of contiguous frequencies (every type of a frequency in the same slice), one per
core (:func:`default_slices`), the last one shorter by the mean's cost (the engine's hint; a half
slice where it is not known): on as many workers as cores, the worker that runs the mean takes the
last slice after it and every worker's load is about equal. A result never depends on the number of
workers, the executor or a resume (bitwise), and on the slicing only at round-off.
"""

from __future__ import annotations

from .channels import GridErrorWarning, check_psd_channels, grid_error_messages, prepare_sweep, psd_rows, psd_z_rows
from .columns import (ColumnTask, PemTask, PsdReducer, column_frequencies, column_slices, default_slices,
                      harmonic_columns, kind_and_unit, pem_tasks, slice_weights)
from .method import PemMethod, PemState, PemWorker, run
from .sizing import PSD_BLOCK, PSD_STORAGE, PSD_TRANSPORT, PemSizing, pem_memory
from ..pseudo_reduction import reducer_column_bytes
from ...results.checks import GRID_ERROR_TOLERANCE

__all__ = ["GRID_ERROR_TOLERANCE", "PSD_BLOCK", "PSD_STORAGE", "PSD_TRANSPORT", "ColumnTask", "GridErrorWarning",
           "PemMethod", "PemSizing", "PemState", "PemTask", "PemWorker", "PsdReducer", "check_psd_channels",
           "column_frequencies", "column_slices", "default_slices", "grid_error_messages", "harmonic_columns",
           "kind_and_unit", "pem_memory", "pem_tasks", "prepare_sweep", "psd_rows", "psd_z_rows",
           "reducer_column_bytes", "run", "slice_weights"]
