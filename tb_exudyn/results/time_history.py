"""TimeHistory: the channels of one run over time (a deterministic run, or one sample).

Saved as a folder holding ``arrays.npz`` (time and a (n_channels, n_t) value matrix, never
unpickled) and ``meta.json`` (channel names and units, provenance, the scenario as TOML), the folder
written whole or not at all and read defensively (:mod:`tb_exudyn.storage`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Mapping

import numpy as np
from numpy.typing import NDArray

from ..errors import ResultsError
from ..scenario import Scenario, scenario_to_toml
from .base import ChannelResult, channel_name
from .metadata import meta_channels, meta_provenance, meta_scenario, meta_str, open_result_folder
from ..storage import (ArraysInMemory, NpzFile, check_increasing, check_members, check_output_times, check_values,
                       freeze, load_json, save_result_folder)
from .kinds import DETERMINISTIC, ResultKind
from .schema import TIME_HISTORY, members, to_xarray

FORMAT = "tb_exudyn.time_history/1"
#: the arrays of arrays.npz, from the schema (:data:`.schema.TIME_HISTORY`): nt output times (at least 2),
#: nc channels (the channels of meta.json, at least one); values finite and at most MAX_VALUE in magnitude
ARRAYS = members(TIME_HISTORY)
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
    #: what it is: one deterministic run (:mod:`.kinds`)
    kind: ClassVar[ResultKind] = DETERMINISTIC
    #: every array this type holds, declared once (:mod:`.schema`): npz and NetCDF
    schema: ClassVar = TIME_HISTORY

    # ---------------------------------------------------------------- access
    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    @property
    def channel_names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        name = channel_name(name, self)
        try:
            return self.channels[name]
        except KeyError:
            head = name.split(".")[0]
            close = [c for c in self.channels if c.startswith(head)][:8] or list(self.channels)[:8]
            raise KeyError(f"no channel {name!r}; e.g. {close}") from None

    def unit(self, name: str) -> str:
        self.index(name)  # a name that is no string or no channel: the errors of index
        return self.units[name]

    def peak(self, name: str) -> tuple[float, float]:
        """(value with the largest magnitude, its time) of a channel."""
        values = self[name]
        i = int(np.argmax(np.abs(values)))
        return float(values[i]), float(self.time[i])

    def arrays(self) -> dict[str, np.ndarray]:
        """Every array of the run by its schema name (:data:`.schema.TIME_HISTORY`): ``time`` and
        ``values``, the channels' values stacked in channel order (what ``arrays.npz`` stores)."""
        names, n = list(self.channels), np.size(self.time)
        return {"time": np.asarray(self.time, dtype=float),
                "values": np.array([self.channels[c] for c in names], dtype=float).reshape(len(names), n)}

    def to_xarray(self) -> Any:
        """The run as an :class:`xarray.Dataset` (:func:`.schema.to_xarray`): ``value`` over channel
        and time, channel names, units and labels as coordinates, provenance as attributes."""
        return to_xarray(self)

    # ---------------------------------------------------------------- files
    def save(self, folder: str | Path) -> Path:
        """Write ``arrays.npz`` and ``meta.json`` as the folder ``folder``, whole or not at all
        (an older result there is replaced; see :func:`tb_exudyn.storage.save_result_folder`).

        What :func:`load_time_history` would refuse is refused first, nothing written: a ResultsError
        naming the file and the key (e.g. a NaN set in Python, a channel of another length)."""
        names = list(self.channels)
        n = np.size(self.time)
        for name in names:
            if np.shape(self.channels[name]) != (n,):
                raise ResultsError(f"{Path(folder) / 'arrays.npz'}: array 'values': channel {name!r} has shape "
                                   f"{np.shape(self.channels[name])}, not ({n},) as 'time' (allowed: one value per "
                                   "output time) [not saved]")
        meta = {
            "format": FORMAT,
            "channels": names,
            "units": [self.units[n] for n in names],
            "provenance": self.provenance,
            "scenario_toml": None if self.scenario is None else scenario_to_toml(self.scenario),
        }
        return save_result_folder(folder, self.arrays(), meta, check=check_folder)


def _read_meta(meta: dict[str, Any], path: Path) -> dict[str, Any]:
    meta_str(meta, "format", path, choices=(FORMAT,))
    names, units = meta_channels(meta, path)
    provenance = meta_provenance(meta, path, optional=True)
    scenario = meta_scenario(meta, path, optional=True)
    return {"names": names, "units": units, "provenance": provenance, "scenario": scenario}


def _check_arrays(path: Path, arrays: Mapping[str, np.ndarray]) -> None:
    check_values(path, arrays, ARRAYS)
    check_output_times(path, arrays["time"])
    check_increasing(path, arrays, ("time",))


def check_folder(folder: Path, arrays: Mapping[str, np.ndarray], meta: dict[str, Any]) -> None:
    """What :func:`load_time_history` checks, on a result about to be saved to ``folder`` (``meta``
    as meta.json will give it back): the check :meth:`TimeHistory.save` runs first."""
    fields = _read_meta(meta, folder / "meta.json")
    check_members(ArraysInMemory(folder / "arrays.npz", arrays), ARRAYS, {"nc": len(fields["names"])}, _MEANING)
    _check_arrays(folder / "arrays.npz", arrays)


def load_time_history(folder: str | Path) -> TimeHistory:
    """Read a TimeHistory written by :meth:`TimeHistory.save`, checking everything before use.

    Raises ResultsError (one line, naming the file) for a missing, foreign, damaged or hostile
    folder: see :mod:`tb_exudyn.storage`; channel names must follow the naming rule and be all different,
    one unit per channel, the arrays' shapes must match the channels and each other, values finite;
    the provenance fields the code reads of the types it writes (:data:`.metadata.PROVENANCE_FIELDS`).
    The arrays are read-only.
    """
    folder = open_result_folder(folder)
    path = folder / "meta.json"
    fields = _read_meta(load_json(path), path)
    names = fields["names"]
    with NpzFile(folder / "arrays.npz") as npz:
        check_members(npz, ARRAYS, {"nc": len(names)}, _MEANING)
        arrays = npz.read_all()
    _check_arrays(npz.path, arrays)
    freeze(arrays)
    values = arrays["values"]
    return TimeHistory(
        time=arrays["time"],
        channels={n: values[i] for i, n in enumerate(names)},
        units=dict(zip(names, fields["units"])),
        scenario=fields["scenario"],
        provenance=dict(fields["provenance"]),
    )
