"""Resource limits before work starts: steps, memory, workers.

Two checks, both before the allocation they guard:

- :func:`check_run_length`, from the scenario alone, before anything is built: the crossing's duration
  and step count finite and at most :data:`MAX_STEPS`, the output step not longer than the crossing
  (each refused with the key to change: ``analysis.time_step``, ``track.lead_in``, ...);
- :func:`check_memory` of a :class:`MemoryEstimate` that a method makes once the model is built (in
  the worker's setup, so that the scenario's channels are known; before any task allocates): the
  main process's part (the reduced maps, results waiting to be reduced) and each worker's (the
  interpreter, the model, the largest task's arrays, its copy sent back), against ``max_memory`` or,
  without one, the memory this machine has available. Refused with a one-line
  :class:`~tb_exudyn.errors.ResourceError` giving the estimate, its largest part and the key to change.

Workers are capped at the cores (:func:`cap_workers`, with a notice).

The constants are measured on the development machine (Python 3.11, numpy 2.4, Exudyn 1.9, Linux):
an interpreter with numpy, scipy, tb_exudyn and Exudyn imported holds 117 MB; a built model 8 MB
(quick) to 35 MB (li_zhu_2011, 53 MB at the peak while its bridge modes are solved).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import Any

from ..errors import ResourceError, SettingError, format_message
from .notices import notice

#: the most integration steps a run may take: 10 million, 1800 times the reference study's 5570
#: (a step of the Exudyn engine takes about 0.5 ms: 10 million steps are 80 min for one run)
MAX_STEPS = 10**7
#: the most tasks a run may have (each a Python object in the main process, and a file in its checkpoint)
MAX_TASKS = 10**6
#: an interpreter with numpy, scipy, tb_exudyn and Exudyn imported (measured 117 MB)
PROCESS_BYTES = 120 * 10**6

_UNITS = {"": 1, "b": 1, "k": 10**3, "kb": 10**3, "m": 10**6, "mb": 10**6, "g": 10**9, "gb": 10**9, "t": 10**12,
          "tb": 10**12, "kib": 2**10, "mib": 2**20, "gib": 2**30, "tib": 2**40}


def format_bytes(n: float) -> str:
    """Bytes as '8.3 GB' (decimal units)."""
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def parse_memory(value: Any, where: str, key: str) -> int | None:
    """A memory size in bytes from an int or a text such as '4GB', '512 MiB', '2e9' (None stays None);
    SettingError naming ``key`` otherwise."""
    if value is None:
        return None
    allowed = "a positive size, e.g. 4GB, 512MB, 2GiB or a number of bytes"
    if isinstance(value, bool):
        raise SettingError(where, key, value, allowed)
    if isinstance(value, (int, float)):
        number, unit = float(value), ""
    else:
        m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*([A-Za-z]*)\s*", str(value))
        if m is None or m.group(2).lower() not in _UNITS:
            raise SettingError(where, key, value, allowed)
        number, unit = float(m.group(1)), m.group(2).lower()
    size = number * _UNITS[unit]
    if not math.isfinite(size) or size < 1:
        raise SettingError(where, key, value, allowed)
    return int(size)


def _read_int(path: str) -> int | None:
    try:
        with open(path, encoding="ascii") as fh:
            text = fh.read().strip()
        return None if text == "max" else int(text)
    except (OSError, ValueError):
        return None


def _cgroup_room() -> int | None:
    """Bytes left under this process's control-group memory limit (a container's), None without one."""
    try:
        with open("/proc/self/cgroup", encoding="utf-8") as fh:
            lines = fh.read().splitlines()
    except OSError:
        return None
    for line in lines:
        hierarchy, controllers, path = (line.split(":", 2) + ["", ""])[:3]
        if hierarchy == "0" and controllers == "":  # cgroup v2
            folders = [f"/sys/fs/cgroup{path}".rstrip("/"), "/sys/fs/cgroup"]
            names = ("memory.max", "memory.current")
        elif "memory" in controllers.split(","):  # cgroup v1
            folders = [f"/sys/fs/cgroup/memory{path}".rstrip("/"), "/sys/fs/cgroup/memory"]
            names = ("memory.limit_in_bytes", "memory.usage_in_bytes")
        else:
            continue
        for folder in folders:
            limit, used = _read_int(f"{folder}/{names[0]}"), _read_int(f"{folder}/{names[1]}")
            if limit is not None and limit < 2**60:
                return max(0, limit - (used or 0))
    return None


def available_memory() -> tuple[int | None, str]:
    """The memory a new run can have now [bytes] and what sets it: the least of the memory this
    machine has available (MemAvailable of /proc/meminfo, else the physical memory), the room left
    under a container's memory limit (cgroup) and this process's address-space limit (ulimit -v).
    (None, ...) when none is known."""
    found: list[tuple[int, str]] = []
    free = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    free = int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    if free is None:
        try:
            free = int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
            free = None
    if free is not None:
        found.append((free, f"the {format_bytes(free)} this machine has available"))
    room = _cgroup_room()
    if room is not None:
        found.append((room, f"the {format_bytes(room)} left under this container's memory limit"))
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft != resource.RLIM_INFINITY and soft > 0:
            found.append((int(soft), f"ulimit -v {format_bytes(soft)}"))
    except (ImportError, OSError, ValueError):  # pragma: no cover - not POSIX
        pass
    return min(found) if found else (None, "an unknown limit")


@dataclass(frozen=True)
class MemoryLimit:
    """What a run may use [bytes] (None: unknown, nothing is refused), how to name it in a message and,
    for a limit the user gave, where and under which key (option or argument)."""

    bytes: int | None
    text: str
    where: str = ""
    key: str = ""


def memory_limit(max_memory: int | None, where: str) -> MemoryLimit:
    """``max_memory`` when given, else the memory available now (:func:`available_memory`)."""
    if max_memory is not None:
        return MemoryLimit(max_memory, f"the max_memory of {format_bytes(max_memory)}", where, "max_memory")
    return MemoryLimit(*available_memory())


@dataclass(frozen=True)
class Part:
    """A share of an estimate: what it is, its bytes, and the key (with its value) that sets its size."""

    what: str
    bytes: int
    key: str = ""
    value: Any = None
    remedy: str = ""


@dataclass(frozen=True)
class MemoryEstimate:
    """The memory of a run: the main process's parts, each worker's parts, the number of worker
    processes (0: the tasks run in the main process, which then holds both)."""

    parent: tuple[Part, ...]
    worker: tuple[Part, ...]
    workers: int

    @property
    def parent_bytes(self) -> int:
        return sum(p.bytes for p in self.parent)

    @property
    def worker_bytes(self) -> int:
        return sum(p.bytes for p in self.worker)

    @property
    def total(self) -> int:
        """Peak bytes of all the run's processes together."""
        if self.workers == 0:
            return self.parent_bytes + self.worker_bytes - PROCESS_BYTES  # one interpreter
        return self.parent_bytes + self.workers * self.worker_bytes

    def largest(self) -> tuple[Part, int, str]:
        """The part that weighs most (with its multiplicity and where it is)."""
        n = max(1, self.workers)
        items = [(p.bytes, p, 1, "in the main process") for p in self.parent if p.key]
        items += [(p.bytes * n, p, n, f"in each of {n} workers" if self.workers else "in the main process")
                  for p in self.worker if p.key]
        _, part, mult, place = max(items, key=lambda x: x[0])
        return part, mult, place


def check_memory(estimate: MemoryEstimate, limit: MemoryLimit, where: str) -> None:
    """ResourceError (one line: the estimate, its largest part, the key to change) when the estimate
    exceeds the limit; when what no setting changes (interpreters, models) exceeds it alone, the
    message names the limit."""
    if limit.bytes is None or estimate.total <= limit.bytes:
        return
    fixed = estimate.total - sum(p.bytes for p in estimate.parent if p.key) \
        - max(1, estimate.workers) * sum(p.bytes for p in estimate.worker if p.key)
    if fixed >= limit.bytes and limit.key:
        raise ResourceError.from_parts(
            limit.where, limit.key, format_bytes(limit.bytes),
            f"at least {format_bytes(fixed)} (more for the run itself)",
            f"the run needs about {format_bytes(estimate.total)}, {format_bytes(fixed)} of it for "
            f"{max(1, estimate.workers)} process(es) alone, more than {limit.text}")
    part, _, place = estimate.largest()
    share = f"{format_bytes(part.bytes)} {place}"
    workers = (f"; or fewer workers ({estimate.workers} now)"
               if estimate.workers > 1 and any(p is part for p in estimate.worker) else "")
    raise ResourceError.from_parts(
        where, part.key, part.value,
        f"a run within the limit: {part.remedy or 'a smaller ' + part.key}{workers}",
        f"the run needs about {format_bytes(estimate.total)} of memory, most of it {part.what} ({share}), more "
        f"than {limit.text}")


def cap_workers(workers: int | None, cores: int, where: str) -> int:
    """The worker processes to start: ``workers`` (None: one per core), at most one per core (with a
    notice when more were asked for)."""
    if workers is None:
        return cores
    if workers > cores:
        notice(f"{where}: workers = {workers} is more than this machine's {cores} cores: {cores} workers run "
               "(more would only share the cores)")
        return cores
    return workers


# ------------------------------------------------------------------------------------- run length
def scenario_where(scenario: Any) -> str:
    """The scenario's file (or name), the first part of a message about it."""
    return getattr(scenario, "where", None) or f"scenario {scenario.name!r}"


def check_run_length(scenario: Any) -> None:
    """Refuse a crossing whose steps overflow or exceed :data:`MAX_STEPS`, or whose output step is
    longer than the crossing (ResourceError naming the key), before anything is built."""
    an, tr = scenario.analysis, scenario.track
    where = scenario_where(scenario)
    try:
        duration = float(scenario.duration)
        steps = duration / an.time_step
    except (OverflowError, ZeroDivisionError, ArithmeticError):
        duration = steps = math.inf
    if not (math.isfinite(steps) and steps <= MAX_STEPS):
        # name the most extreme of the values that set the step count
        rest = (scenario.bridge.length + scenario.train.length) or 1.0
        if an.time_step < 1e-6:
            key, value = "analysis.time_step", an.time_step
        elif tr.lead_in + tr.run_out > 100.0 * rest:
            key = "track.lead_in" if tr.lead_in >= tr.run_out else "track.run_out"
            value = tr.lead_in if tr.lead_in >= tr.run_out else tr.run_out
        elif scenario.bridge.length > 100.0 * (tr.lead_in + tr.run_out + scenario.train.length):
            key, value = "bridge.spans", list(scenario.bridge.spans)
        elif scenario.speed_kmh < 1.0:
            key, value = "speed_kmh", scenario.speed_kmh
        else:
            key, value = "analysis.time_step", an.time_step
        allowed = f"at most {MAX_STEPS:.0e} steps: larger time_step, shorter lead_in/run_out"
        if key == "speed_kmh":  # the speed at which the crossing takes MAX_STEPS steps
            slowest = 3.6 * (tr.lead_in + scenario.bridge.length + scenario.train.length + tr.run_out) \
                / (MAX_STEPS * an.time_step)
            unit = 10.0 ** (math.floor(math.log10(slowest)) - 2)  # rounded up to 3 digits: that speed is allowed
            allowed = f"at most {MAX_STEPS:.0e} steps: speed_kmh >= {math.ceil(slowest / unit) * unit:.3g}, or a larger time_step"
        raise ResourceError(format_message(
            where, key, value, allowed,
            f"{steps:.4g} steps of {an.time_step:g} s ({duration:.4g} s)"))
    if an.output_step > duration:
        raise ResourceError(format_message(
            where, "analysis.output_step", an.output_step, f"at most the crossing's duration, {duration:.4g} s",
            "longer than the crossing: the run would go on to a whole output step"))


#: bytes per entry of the n x n linearised system (n ODE2 coordinates): Exudyn's dense M, K, D, their numpy
#: copies and the mode table's state matrix; measured 7.6 copies of 8 bytes (40 ICE cars, n = 1694: 174 MB)
SYSTEM_BYTES_PER_ENTRY = 10 * 8
#: ODE2 coordinates the builder gives a vehicle: 6 per rigid-body node (a car on two bogies: body, two
#: bogies, four wheelsets); a sprung mass has 1 (2 with a wheel mass), a moving force none
CAR_COORDINATES = 42


def vehicle_coordinates(vehicle: Any) -> int:
    """The ODE2 coordinates of one vehicle in the built model (:data:`CAR_COORDINATES` for a car)."""
    if vehicle.kind == "moving_force":
        return 0
    if vehicle.kind == "sprung_mass":
        return 1 + int(vehicle.wheel_mass > 0.0)
    return CAR_COORDINATES


def check_system_size(scenario: Any, n_bridge_modes: int, limit: int | None = None) -> None:
    """Refuse (ResourceError naming ``train.vehicles``, or the bridge's modes) a train-bridge system whose
    linearised matrices would not fit ``limit`` bytes (None: the memory this machine has available), once
    the bridge's modes are known and before the vehicles are built: every run and the mode table make
    the dense n x n system (:data:`SYSTEM_BYTES_PER_ENTRY`)."""
    vehicles = scenario.train.vehicles
    n_veh = sum(vehicle_coordinates(v) for v in vehicles)
    n = int(n_bridge_modes) + n_veh
    text = f"the limit of {format_bytes(limit)}" if limit is not None else ""
    if limit is None:
        limit, text = available_memory()
    need = SYSTEM_BYTES_PER_ENTRY * n * n
    if limit is None or need <= limit:
        return
    most = int(math.sqrt(limit / SYSTEM_BYTES_PER_ENTRY))  # coordinates that fit
    reason = f"{len(vehicles)} vehicles need about {format_bytes(need)}, over {text}"
    if n_veh >= n_bridge_modes:
        fit = max(0, (most - int(n_bridge_modes)) * len(vehicles) // n_veh)
        raise ResourceError(format_message(scenario_where(scenario), "train.vehicles", [v.name for v in vehicles],
                                           f"at most about {fit} such vehicles", reason))
    raise ResourceError(format_message(
        scenario_where(scenario), "analysis.mode_max_frequency", scenario.analysis.mode_max_frequency,
        f"at most about {max(0, most - n_veh)} bridge modes: a lower analysis.mode_max_frequency, an "
        "analysis.max_modes or fewer bridge.spans", reason))


def check_task_count(n_tasks: int, where: str, key: str, value: Any, remedy: str) -> None:
    """Refuse more than :data:`MAX_TASKS` tasks (ResourceError naming ``key``), before they are made."""
    if n_tasks > MAX_TASKS:
        raise ResourceError(format_message(where, key, value, f"at most {MAX_TASKS:.0e} tasks: {remedy}",
                                           f"{n_tasks:.4g} tasks"))


def describe_counts(**counts: int) -> str:
    """'51 channels x 200 frequencies x 558 output times'."""
    return " x ".join(f"{v} {k.replace('_', ' ')}" for k, v in counts.items())


def model_bytes(engine: Any) -> int:
    """Bytes of a built model (Exudyn's system, the modal bridge, the linear system), at its peak while
    the bridge modes are solved: 8 MB and 0.2 MB per coordinate (measured 8 MB for quick's 52
    coordinates, 53 MB for li_zhu_2011's 224)."""
    return 8 * 10**6 + 200_000 * int(engine.n_coordinates)


def column_bytes(engine: Any) -> int:
    """Bytes per complex column of a built engine while it integrates (an upper estimate).

    An engine of separate runs (``single_columns``: Exudyn) holds each run's outputs at every output
    time (complex) and Exudyn's recording of every coordinate's displacement, velocity and
    acceleration; a linear engine (batched, dense) the column's state: displacement, velocity,
    acceleration, predictors and the outputs' gathers over the coordinates (about 16 float64 pairs
    per coordinate), the contact rows' inputs, and the outputs (complex, with their squares).
    """
    n_out, n_t, n = len(engine.outputs.names), engine.steps.n_outputs, engine.n_coordinates
    if engine.single_columns:
        return 16 * n_out * n_t + 48 * n * n_t
    return 256 * n + 48 * n_out


__all__ = ["MAX_STEPS", "MAX_TASKS", "PROCESS_BYTES", "MemoryEstimate", "MemoryLimit", "Part", "available_memory",
           "cap_workers", "check_memory", "check_run_length", "check_system_size", "check_task_count", "column_bytes",
           "describe_counts",
           "format_bytes",
           "memory_limit", "model_bytes", "parse_memory", "scenario_where", "vehicle_coordinates"]
