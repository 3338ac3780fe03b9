"""TimeHistory: the channels of one run over time (a deterministic run, or one sample).

Saved as a folder holding ``arrays.npz`` (time and a (n_channels, n_t) value matrix, read with
allow_pickle=False) and ``meta.json`` (channel names and units, provenance, the scenario as TOML),
both written atomically (temporary file, then rename).
"""

from __future__ import annotations

import fnmatch
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from ..scenario import Scenario, scenario_from_dict, scenario_to_toml
from .storage import load_json, load_npz, save_json_atomic, save_npz_atomic

FORMAT = "tb_exudyn.time_history/1"


@dataclass(frozen=True, eq=False)
class TimeHistory:
    """Channel values of one run.

    Attributes
    ----------
    time : (n_t,) output times [s]; t = 0 when the first axle is at x = -lead_in
    channels : channel name -> (n_t,) values, in catalogue order (bridge first, then car1, ...)
    units : channel name -> unit
    scenario : the scenario that was run (None if unknown)
    provenance : versions, run time, steps, solver settings, excitation
    """

    time: NDArray[np.float64]
    channels: Mapping[str, NDArray[np.float64]]
    units: Mapping[str, str]
    scenario: Scenario | None = None
    provenance: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = np.asarray(self.time).shape
        for name, values in self.channels.items():
            if np.asarray(values).shape != n:
                raise ValueError(f"channel {name!r} has shape {np.asarray(values).shape}, time has {n}")
            if name not in self.units:
                raise ValueError(f"channel {name!r} has no unit")

    # ---------------------------------------------------------------- access
    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        try:
            return self.channels[name]
        except KeyError:
            head = name.split(".")[0]
            close = [c for c in self.channels if c.startswith(head)][:8] or list(self.channels)[:8]
            raise KeyError(f"no channel {name!r}; e.g. {close}") from None

    def unit(self, name: str) -> str:
        return self.units[name]

    def select(self, patterns: str | list[str] | tuple[str, ...]) -> list[str]:
        """Channel names matching glob pattern(s), in stored order."""
        pats = [patterns] if isinstance(patterns, str) else list(patterns)
        return [c for c in self.channels if any(fnmatch.fnmatchcase(c, p) for p in pats)]

    def peak(self, name: str) -> tuple[float, float]:
        """(value with the largest magnitude, its time) of a channel."""
        values = self[name]
        i = int(np.argmax(np.abs(values)))
        return float(values[i]), float(self.time[i])

    # ---------------------------------------------------------------- files
    def save(self, folder: str | Path) -> Path:
        """Write ``arrays.npz`` and ``meta.json`` into ``folder`` (atomically, arrays first)."""
        folder = Path(folder)
        names = list(self.channels)
        values = np.array([self.channels[n] for n in names], dtype=float).reshape(len(names), np.size(self.time))
        save_npz_atomic(folder / "arrays.npz", {"time": np.asarray(self.time, dtype=float), "values": values})
        meta = {
            "format": FORMAT,
            "channels": names,
            "units": [self.units[n] for n in names],
            "provenance": self.provenance,
            "scenario_toml": None if self.scenario is None else scenario_to_toml(self.scenario),
        }
        save_json_atomic(folder / "meta.json", meta)
        return folder


def load_time_history(folder: str | Path) -> TimeHistory:
    """Read a TimeHistory written by :meth:`TimeHistory.save`."""
    folder = Path(folder)
    meta = load_json(folder / "meta.json")
    if meta.get("format") != FORMAT:
        raise ValueError(f"{folder}: not a tb_exudyn time history (format {meta.get('format')!r})")
    arrays = load_npz(folder / "arrays.npz")
    names = list(meta["channels"])
    values = arrays["values"]
    if values.shape != (len(names), arrays["time"].size):
        raise ValueError(f"{folder}: arrays.npz holds {values.shape} values for {len(names)} channels")
    toml_text = meta.get("scenario_toml")
    scenario = None if toml_text is None else scenario_from_dict(tomllib.loads(toml_text), f"{folder}/meta.json")
    return TimeHistory(
        time=arrays["time"],
        channels={n: values[i] for i, n in enumerate(names)},
        units=dict(zip(names, meta["units"])),
        scenario=scenario,
        provenance=dict(meta.get("provenance", {})),
    )
