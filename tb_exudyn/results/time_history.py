"""TimeHistory: the channels of one run over time (a deterministic run, or one sample).

Saved as a folder holding ``arrays.npz`` (time and a (n_channels, n_t) value matrix, never
unpickled) and ``meta.json`` (channel names and units, provenance, the scenario as TOML), the folder
written whole or not at all and read defensively (:mod:`.storage`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from ..scenario import Scenario, scenario_to_toml
from .base import ChannelResult
from .metadata import meta_channels, meta_dict, meta_scenario, meta_str, open_result_folder
from .storage import Member, NpzFile, check_increasing, check_members, check_values, load_json, save_result_folder

FORMAT = "tb_exudyn.time_history/1"
#: the arrays of arrays.npz: nt output times, nc channels (the channels of meta.json)
ARRAYS = {"time": Member(("nt",)), "values": Member(("nc", "nt"))}
_MEANING = {"nt": "the length of 'time'", "nc": "the number of channels in meta.json"}


@dataclass(frozen=True, eq=False)
class TimeHistory(ChannelResult):
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

    default_plot = "history"

    # ---------------------------------------------------------------- access
    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    @property
    def channel_names(self) -> tuple[str, ...]:
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

    def peak(self, name: str) -> tuple[float, float]:
        """(value with the largest magnitude, its time) of a channel."""
        values = self[name]
        i = int(np.argmax(np.abs(values)))
        return float(values[i]), float(self.time[i])

    # ---------------------------------------------------------------- files
    def save(self, folder: str | Path) -> Path:
        """Write ``arrays.npz`` and ``meta.json`` as the folder ``folder``, whole or not at all
        (an older result there is replaced; see :func:`.storage.save_result_folder`)."""
        names = list(self.channels)
        values = np.array([self.channels[n] for n in names], dtype=float).reshape(len(names), np.size(self.time))
        meta = {
            "format": FORMAT,
            "channels": names,
            "units": [self.units[n] for n in names],
            "provenance": self.provenance,
            "scenario_toml": None if self.scenario is None else scenario_to_toml(self.scenario),
        }
        return save_result_folder(folder, {"time": np.asarray(self.time, dtype=float), "values": values}, meta)


def load_time_history(folder: str | Path) -> TimeHistory:
    """Read a TimeHistory written by :meth:`TimeHistory.save`, checking everything before use.

    Raises ResultsError (one line, naming the file) for a missing, foreign, damaged or hostile
    folder: see :mod:`.storage`; channel names must follow the naming rule and be all different,
    one unit per channel, the arrays' shapes must match the channels and each other, values finite.
    """
    folder = open_result_folder(folder)
    path = folder / "meta.json"
    meta = load_json(path)
    meta_str(meta, "format", path, choices=(FORMAT,))
    names, units = meta_channels(meta, path)
    provenance = meta_dict(meta, "provenance", path, optional=True)
    scenario = meta_scenario(meta, path, optional=True)
    with NpzFile(folder / "arrays.npz") as npz:
        check_members(npz, ARRAYS, {"nc": len(names)}, _MEANING)
        arrays = npz.read_all()
    check_values(npz.path, arrays, ARRAYS)
    check_increasing(npz.path, arrays, ("time",))
    values = arrays["values"]
    return TimeHistory(
        time=arrays["time"],
        channels={n: values[i] for i, n in enumerate(names)},
        units=dict(zip(names, units)),
        scenario=scenario,
        provenance=dict(provenance),
    )
