"""PEM's memory estimate, before any task allocates (:func:`pem_memory`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...execution.resources import PROCESS_BYTES, MemoryEstimate, MemoryLimit, Part, column_bytes, describe_counts, model_bytes
from ..pseudo_reduction import reducer_column_bytes
from ..reduction import engine_plan

#: largest messages (the reference study's map is 420 MB in float64)
PSD_TRANSPORT = np.float32
#: precision in which a result keeps its PSD maps (sigma^2 is float64 throughout): float32's relative
#: rounding of 6e-8 is far below every stated tolerance, and halves the files
PSD_STORAGE = np.float32
#: output times written to a task's PSD map at once (contiguous runs of the time axis)
PSD_BLOCK = 16


@dataclass(frozen=True)
class PemSizing:
    """What the memory estimate of a sweep needs besides the built model (:func:`pem_memory`)."""

    n_freq: int
    n_types: int
    task_freqs: int  # frequencies of the largest task
    keep_psd: bool
    workers: int  # worker processes (0: in the main process)
    output_step: float
    limit: MemoryLimit | None  # None: what the machine running the setup has available
    where: str
    psd_channels: int | None = None  # channels whose PSD map is kept (None: all)
    psd_task_rows: int | None = None  # rows of a task's PSD map (psd_z_rows; None: one per output channel)


def pem_memory(s: PemSizing, engine: Any) -> MemoryEstimate:
    """The memory of a sweep on a built ``engine`` [bytes]: in the main process the kept PSD map (float32)
    and the task results waiting or arriving (a pool: one waiting and one arriving, which is briefly
    there twice, as the received message and the array); in each worker the largest task's PSD map
    (float32; a pool sends a copy), its columns' state, the model, the interpreter."""
    n_ch, n_t = len(engine.outputs.names), engine.steps.n_outputs
    pool = s.workers > 0
    n_f = ("analysis.n_freq", s.n_freq)
    remedy = ("a smaller analysis.n_freq, fewer analysis.channels or a larger analysis.output_step"
              + (", fewer PSD maps (psd_channels), or keep_psd=False" if s.keep_psd else ""))
    n_task = n_ch if s.psd_task_rows is None else s.psd_task_rows
    task_map = 4 * n_task * s.task_freqs * n_t if s.keep_psd else 0
    task_var = 8 * n_t * s.n_types * n_ch
    m = s.task_freqs * s.n_types
    n_kept = n_ch if s.psd_channels is None else s.psd_channels
    parent = (
        Part(f"the PSD map ({describe_counts(channels=n_kept, frequencies=s.n_freq, output_times=n_t)}, float32)",
             4 * n_kept * s.n_freq * n_t if s.keep_psd else 0, *n_f, remedy),
        Part("the task results waiting or arriving", 3 * (task_map + task_var) if pool else 0, *n_f, remedy),
        Part("sigma, mean and the variances per type", 8 * n_ch * n_t * (s.n_types + 6), "analysis.output_step",
             s.output_step, "a larger analysis.output_step, or fewer analysis.channels"),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    worker = (
        Part(f"a task's PSD map ({describe_counts(channels=n_task, frequencies=s.task_freqs, output_times=n_t)}, "
             "float32" + (", and its copy sent back" if pool else "") + ")",
             (2 if pool else 1) * task_map + task_map // max(1, n_t) * PSD_BLOCK, *n_f, remedy),
        Part(f"the state of a task's {m} columns", m * column_bytes(engine) + task_var, *n_f, remedy),
        Part(f"the reduction's buffers of a task's {m} columns", m * reducer_column_bytes(engine_plan(engine), n_ch),
             *n_f, remedy),
        Part("the model", model_bytes(engine)),
        Part("the engine's compiled code", engine.code_bytes(True)),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    return MemoryEstimate(parent, worker, s.workers)


__all__ = ["PSD_BLOCK", "PSD_STORAGE", "PSD_TRANSPORT", "PemSizing", "pem_memory"]
