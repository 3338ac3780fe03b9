"""Hostile inputs of issue 29 ("an imported modal bridge") as data, in the form of cases.py.

A ``modal_table`` bridge's tables (docs/modal_bridge.md) with what a user's export can get wrong: modes
that are not mass-normalised, stations outside the bridge, a track line that does not cover the deck,
a missing column, a value that is no number, frequencies out of order, an unknown mode type, a missing
file, a shape column of a mode the modes file does not have; and ``tb-exudyn export-modes`` asked for
what it cannot do. Every case ends in exit status 2 with one line naming the file (or the option) and
the column or key, no traceback, and nothing written (tests/reliability/test_modal.py).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from .cases import Case, Run

GROUP = "modal"

L = 20.0
#: the stations of the good shapes table
XS = [L * i / 10 for i in range(11)]


def _modes_text(rows: list[list[str]] | None = None) -> str:
    rows = rows or [["1", "5.0", "0.02", "vertical", "1.0"], ["2", "9.0", "0.02", "lateral", "1.0"]]
    return "mode,frequency_hz,damping_ratio,type,modal_mass\n" + "".join(",".join(r) + "\n" for r in rows)


def _shapes_text(xs: list[float] | None = None, extra: str = "", drop: str = "", bad: tuple[int, str] | None = None) -> str:
    """Two modes: a vertical and a lateral sine of amplitude sqrt(2 / (m L)) (m = 1e4 kg/m)."""
    amp = math.sqrt(2.0 / (1.0e4 * L))
    cols = ["x", "y1", "z1", "rx1", "y2", "z2", "rx2"] + ([extra] if extra else [])
    cols = [c for c in cols if c != drop]
    lines = [",".join(cols)]
    for i, x in enumerate(xs or XS):
        s = amp * math.sin(math.pi * min(max(x, 0.0), L) / L)
        value = {"x": x, "y1": 0.0, "z1": s, "rx1": 0.0, "y2": s, "z2": 0.0, "rx2": 0.0, extra: 0.0}
        row = [repr(value[c]) for c in cols]
        if bad is not None and bad[0] == i:
            row[1] = bad[1]
        lines.append(",".join(row))
    return "\n".join(lines) + "\n"


def _bridge(d: Path, *, modes: str | None = None, shapes: str | None = None, stations: str | None = None,
            shapes_name: str = "shapes.csv") -> Path:
    """bridge.toml with its tables in d (the good ones unless given); returns bridge.toml."""
    (d / "modes.csv").write_text(modes if modes is not None else _modes_text())
    if shapes_name == "shapes.csv":
        (d / "shapes.csv").write_text(shapes if shapes is not None else _shapes_text())
    text = (f'kind = "modal_table"\nname = "imported"\nspans = [{L!r}]\nmodes = "modes.csv"\n'
            f'shapes = "{shapes_name}"\n')
    if stations is not None:
        (d / "stations.csv").write_text(stations)
        text += 'stations = "stations.csv"\n'
    p = d / "bridge.toml"
    p.write_text(text)
    return p


def _scenario(d: Path, mode_max_frequency: float = 60.0) -> Path:
    text = ('name = "imported"\nspeed_kmh = 200.0\nbridge = "bridge.toml"\n\n[train]\nvehicles = ["ice_motor"]\n\n'
            '[track]\nirregularities = ["german_low.vertical"]\nlead_in = 85.0\nrun_out = 10.0\n\n'
            f'[analysis]\nmode_max_frequency = {mode_max_frequency!r}\n')
    p = d / "sc.toml"
    p.write_text(text)
    return p


def _modes(d: Path) -> tuple[str, ...]:
    return ("modes", str(_scenario(d)))


def _run(d: Path) -> tuple[str, ...]:
    return ("run", str(_scenario(d)), "--out", str(d / "out"), "--no-figures", "--no-progress")


# ------------------------------------------------------------------------------------ modes.csv
def _not_mass_normalised(d: Path) -> Run:
    _bridge(d, modes=_modes_text([["1", "5.0", "0.02", "vertical", "250000.0"], ["2", "9.0", "0.02", "lateral", "1.0"]]))
    return Run(argv=_modes(d), expect=(str(d / "modes.csv"), "'modal_mass[row 1]'", "not mass-normalised"))


def _not_mass_normalised_run(d: Path) -> Run:
    _bridge(d, modes=_modes_text([["1", "5.0", "0.02", "vertical", "1.0"], ["2", "9.0", "0.02", "lateral", "0.5"]]))
    return Run(argv=_run(d), expect=(str(d / "modes.csv"), "'modal_mass[row 2]'", "not mass-normalised"))


def _not_ascending(d: Path) -> Run:
    _bridge(d, modes=_modes_text([["1", "9.0", "0.02", "vertical", "1.0"], ["2", "5.0", "0.02", "lateral", "1.0"]]))
    return Run(argv=_modes(d), expect=(str(d / "modes.csv"), "'frequency_hz[row 2]'", "ascending"))


def _unknown_type(d: Path) -> Run:
    _bridge(d, modes=_modes_text([["1", "5.0", "0.02", "bending", "1.0"], ["2", "9.0", "0.02", "lateral", "1.0"]]))
    return Run(argv=_modes(d), expect=(str(d / "modes.csv"), "'type[row 1]'", "vertical, lateral"))


def _damping_out_of_range(d: Path) -> Run:
    _bridge(d, modes=_modes_text([["1", "5.0", "1.5", "vertical", "1.0"], ["2", "9.0", "0.02", "lateral", "1.0"]]))
    return Run(argv=_modes(d), expect=(str(d / "modes.csv"), "'damping_ratio[row 1]'", "0 <= damping_ratio < 1"))


def _missing_modes_column(d: Path) -> Run:
    _bridge(d, modes="mode,frequency_hz,type,modal_mass\n1,5.0,vertical,1.0\n")
    return Run(argv=_modes(d), expect=(str(d / "modes.csv"), "'damping_ratio'", "missing column"))


# ------------------------------------------------------------------------------------ shapes.csv
def _station_outside(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(XS + [L + 5.0]))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'x[row 12]'", "outside the bridge", "0 <= x <= 20 m"))


def _station_before_start(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text([-2.0] + XS))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'x[row 1]'", "outside the bridge"))


def _track_off_the_deck(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(XS[:8]))  # the track line ends 6 m before the bridge's end
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'x[row 8]'", "does not cover the deck"))


def _stations_not_in_order(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text([0.0, 10.0, 5.0, 20.0]))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'x[row 3]'", "not ascending"))


def _station_three_times(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text([0.0, 10.0, 10.0, 10.0, 20.0]))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'x[row 4]'", "at most twice"))


def _missing_shape_column(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(drop="z2"))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'z2'", "missing column"))


def _shape_of_a_mode_too_many(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(extra="y3"))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'y3'", "a mode the modes file does not have"))


def _not_a_number(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(bad=(2, "0.1x")))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'y1[row 3]'", "not a number"))


def _not_finite(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text(bad=(4, "nan")))
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'y1[row 5]'", "not finite"))


def _short_row(d: Path) -> Run:
    _bridge(d, shapes=_shapes_text() + "20.0,0.0\n")
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "'row 12'", "wrong number of values"))


def _missing_file(d: Path) -> Run:
    _bridge(d, shapes_name="nothing.csv")
    return Run(argv=_modes(d), expect=(str(d / "nothing.csv"), "file not found"))


def _table_too_large(d: Path) -> Run:
    _bridge(d)
    with open(d / "shapes.csv", "r+b") as fh:  # a sparse 65 MiB file: refused by its size before it is read
        fh.truncate(65 * 2**20)
    return Run(argv=_modes(d), expect=(str(d / "shapes.csv"), "at most 64 MiB"), isolate=True)


# ------------------------------------------------------------------------------------ stations.csv
def _output_station_outside(d: Path) -> Run:
    _bridge(d, stations="station,x,y1,z1,rx1,y2,z2,rx2\nspan1.mid,10.0,0,1e-3,0,1e-3,0,0\nfar,35.0,0,0,0,0,0,0\n")
    return Run(argv=_modes(d), expect=(str(d / "stations.csv"), "'x[row 2]'", "outside the bridge"))


def _station_name_twice(d: Path) -> Run:
    _bridge(d, stations="station,x,y1,z1,rx1,y2,z2,rx2\nspan1.mid,10.0,0,1e-3,0,1e-3,0,0\nspan1.mid,10.0,0,0,0,0,0,0\n")
    return Run(argv=_modes(d), expect=(str(d / "stations.csv"), "'station[row 2]'", "unique name"))


def _span_station_off_its_place(d: Path) -> Run:
    _bridge(d, stations="station,x,y1,z1,rx1,y2,z2,rx2\nspan1.mid,12.0,0,1e-3,0,1e-3,0,0\n")
    return Run(argv=_modes(d), expect=(str(d / "stations.csv"), "'x[row 1]'", "10 m, where the spans put span1.mid"))


def _station_x_not_a_number(d: Path) -> Run:
    _bridge(d, stations="station,x,y1,z1,rx1,y2,z2,rx2\npier1.top,top,0,1e-3,0,1e-3,0,0\n")
    return Run(argv=_modes(d), expect=(str(d / "stations.csv"), "'x[row 1]'", "not a finite number"))


# ------------------------------------------------------------------------------------ the scenario's keys
def _no_mode_below_max_frequency(d: Path) -> Run:
    _bridge(d)
    p = _scenario(d, mode_max_frequency=2.0)
    return Run(argv=("modes", str(p)), expect=(str(p), "'analysis.mode_max_frequency'", "lowest mode"))


def _code_check_refuses(d: Path) -> Run:
    p = _bridge(d)
    given = f"../{d.name}/{p.name}"  # the file as typed (the case runs in d/../cwd), not its name inside
    return Run(argv=("check", given, "--line-speed-kmh", "200", "--out", str(d / "out")),
               expect=(f"'BRIDGE' = {given!r}", "modal_table bridge has no section data"))


# ------------------------------------------------------------------------------------ export-modes
def _export_over_existing(d: Path) -> Run:
    out = d / "exported"
    out.mkdir()
    (out / "bridge.toml").write_text("# the user's own\n")
    return Run(argv=("export-modes", "single_span_32m", "--out", str(out)),
               expect=("'--out'", str(out / "bridge.toml"), "exists", "--overwrite"))


def _export_a_modal_table(d: Path) -> Run:
    p = _bridge(d)
    return Run(argv=("export-modes", str(p), "--out", str(d / "exported")),
               expect=("'BRIDGE'", "modal_table has no finite-element model"))


def _export_below_lowest_mode(d: Path) -> Run:
    return Run(argv=("export-modes", "single_span_32m", "--out", str(d / "exported"), "--max-frequency", "0.5"),
               expect=("'--max-frequency'", "lowest mode"))


def _export_nan_frequency(d: Path) -> Run:
    return Run(argv=("export-modes", "single_span_32m", "--out", str(d / "exported"), "--max-frequency", "nan"),
               expect=("'--max-frequency'", "finite frequency > 0"))


_BUILDS: list[tuple[str, Callable[[Path], Run]]] = [
    ("modal_not_mass_normalised", _not_mass_normalised),
    ("modal_not_mass_normalised_run", _not_mass_normalised_run),
    ("modal_frequencies_not_ascending", _not_ascending),
    ("modal_unknown_mode_type", _unknown_type),
    ("modal_damping_out_of_range", _damping_out_of_range),
    ("modal_modes_column_missing", _missing_modes_column),
    ("modal_station_outside_bridge", _station_outside),
    ("modal_station_before_start", _station_before_start),
    ("modal_track_off_the_deck", _track_off_the_deck),
    ("modal_stations_not_in_order", _stations_not_in_order),
    ("modal_station_three_times", _station_three_times),
    ("modal_shape_column_missing", _missing_shape_column),
    ("modal_shape_of_unknown_mode", _shape_of_a_mode_too_many),
    ("modal_shape_not_a_number", _not_a_number),
    ("modal_shape_not_finite", _not_finite),
    ("modal_shape_short_row", _short_row),
    ("modal_shapes_file_missing", _missing_file),
    ("modal_table_too_large", _table_too_large),
    ("modal_output_station_outside", _output_station_outside),
    ("modal_station_name_twice", _station_name_twice),
    ("modal_span_station_off_its_place", _span_station_off_its_place),
    ("modal_station_x_not_a_number", _station_x_not_a_number),
    ("modal_no_mode_below_max_frequency", _no_mode_below_max_frequency),
    ("modal_code_check_refuses", _code_check_refuses),
    ("modal_export_over_existing", _export_over_existing),
    ("modal_export_a_modal_table", _export_a_modal_table),
    ("modal_export_below_lowest_mode", _export_below_lowest_mode),
    ("modal_export_nan_frequency", _export_nan_frequency),
]

CASES_MODAL: list[Case] = [Case(name, GROUP, build) for name, build in _BUILDS]
