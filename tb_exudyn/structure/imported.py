"""A bridge given by its modes in CSV tables (``kind = "modal_table"``), and our FE's modes written so.

The format (docs/modal_bridge.md) is what any FE program can write: ``modes.csv`` (one row per mode:
``mode, frequency_hz, damping_ratio, type, modal_mass``), ``shapes.csv`` (one row per station x along
the track: ``x`` and, per mode k, ``y<k>, z<k>, rx<k>`` at the track line, optionally their slopes
``dy<k>, dz<k>, drx<k>`` along x) and, optionally, ``stations.csv`` (the output stations:
``station, x`` and ``y<k>, z<k>, rx<k>``).

Between stations the shapes are cubic Hermite polynomials of the values and slopes at the two ends,
so the shapes are exact at the stations. Without slope columns the slopes are those of a cubic spline
(not-a-knot) through the stations of each piece (a station given twice ends one piece and starts the
next: a support where the slope jumps, or where two girders meet). A station given twice may carry
different values and slopes on its two sides; a point exactly there belongs to the second row, as in
the FE model (an element's start belongs to it). Our FE's modes (:func:`export_modes`) are written at
both ends of every girder element with their exact slopes: each element's shape is a cubic (bending)
plus a linear function (twist), which the Hermite cubic of its end values and slopes reproduces, so a
round trip gives the FE bridge's rail shapes to round-off.

:func:`imported_modal_bridge` reads the tables into a :class:`~.modal.ModalBridge`. Every error in a
table is a :class:`~tb_exudyn.errors.ScenarioError` naming the file, the column and the row.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
from scipy.linalg import solve_banded

from ..errors import ScenarioError
from ..files import MIB, FileRefused, output_targets, read_text, write_output
from ..scenario.model import ModalTable
from ..scenario.sections import track_lines
from ..scenario.toml_io import dumps_toml
from ..system.derived import station_positions
from .assembly import SPAN_RANGE, StructureError
from .fe import (MECHANISM_FREQUENCY, RailShapeEvaluator, bridge_modes, line_shape_evaluator, modal_bridge_from_modes,
                 rayleigh_damping_ratios)
from .modal import ModalBridge, TrackShapes, track_stations

#: the mode types a modes.csv may name (those our FE gives)
MODE_TYPES = ("vertical", "lateral", "torsion", "longitudinal", "pier", "mixed")
#: |modal_mass - 1| allowed: the shapes must be mass-normalised (phi^T M phi = 1)
MODAL_MASS_TOLERANCE = 1e-3
#: how far [m] the first and last station may lie from the bridge's ends (x = 0 and sum(spans))
X_TOLERANCE = 1e-6
#: largest table read [bytes] (64 MiB: e.g. 200 modes at 2000 stations with slopes, 53 MB; parsed, a few hundred MB)
MAX_TABLE_BYTES = 64 * MIB
#: the components of a shape column, in the order of RailShapes' (y, z, rx)
COMPONENTS = ("y", "z", "rx")


# ============================================================================================ reading


def _error(path: str, key: str, value: object, allowed: str, reason: str = "") -> ScenarioError:
    """The ScenarioError of a table (numpy scalars shown as plain numbers)."""
    return ScenarioError(path, key, value.item() if isinstance(value, np.generic) else value, allowed, reason)


def _rows(path: str) -> tuple[list[str], list[list[str]]]:
    """Header and data rows of a CSV file (lines starting with '#' and blank lines skipped)."""
    allowed = f"a regular UTF-8 CSV file of at most {MAX_TABLE_BYTES // MIB} MiB"
    try:
        text = read_text(path, max_bytes=MAX_TABLE_BYTES, follow_symlinks=True)
    except FileNotFoundError:
        raise _error(path, "<file>", path, "an existing CSV file", "file not found") from None
    except (FileRefused, OSError) as exc:
        raise _error(path, "<file>", path, allowed, str(exc)) from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    rows = [[c.strip() for c in r] for r in csv.reader(lines)]
    if not rows:
        raise _error(path, "<file>", path, "a header line and at least one data row", "empty table")
    header, data = rows[0], rows[1:]
    if len(set(header)) != len(header):
        dup = next(h for h in header if header.count(h) > 1)
        raise _error(path, dup, dup, "each column once", "repeated column")
    for i, r in enumerate(data):
        if len(r) != len(header):
            raise _error(path, f"row {i + 1}", len(r), f"{len(header)} values, one per column of the header",
                                "wrong number of values")
    if not data:
        raise _error(path, "<file>", path, "at least one data row below the header", "no data")
    return header, data


def _column(path: str, header: list[str], data: list[list[str]], name: str, allowed: str) -> list[str]:
    if name not in header:
        raise _error(path, name, "<missing>", allowed, "missing column")
    j = header.index(name)
    return [r[j] for r in data]


def _numbers(path: str, name: str, texts: list[str], allowed: str = "a finite number") -> np.ndarray:
    out = np.empty(len(texts))
    for i, t in enumerate(texts):
        try:
            out[i] = float(t)
        except ValueError:
            raise _error(path, f"{name}[row {i + 1}]", t, allowed, "not a number") from None
        if not math.isfinite(out[i]):
            raise _error(path, f"{name}[row {i + 1}]", t, allowed, "not finite")
    return out


def read_modes(path: str) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """(frequencies [Hz], damping ratios, types) of a modes.csv; refuses modes that are not
    mass-normalised (modal_mass not 1 within :data:`MODAL_MASS_TOLERANCE`), frequencies not ascending."""
    header, data = _rows(path)
    cols = "columns mode, frequency_hz, damping_ratio, type, modal_mass"
    number = _numbers(path, "mode", _column(path, header, data, "mode", cols), "the mode number 1, 2, ...")
    for i, k in enumerate(number):
        if k != i + 1:
            raise _error(path, f"mode[row {i + 1}]", k, f"{i + 1}: modes numbered 1, 2, ... in order",
                                "wrong mode number")
    freq = _numbers(path, "frequency_hz", _column(path, header, data, "frequency_hz", cols))
    for i, f in enumerate(freq):
        if f < MECHANISM_FREQUENCY:
            raise _error(path, f"frequency_hz[row {i + 1}]", f, f">= {MECHANISM_FREQUENCY:g} Hz",
                                "no bridge mode (a mechanism or a rigid-body mode)")
        if i and f < freq[i - 1]:
            raise _error(path, f"frequency_hz[row {i + 1}]", f, f">= {freq[i - 1]:g} Hz (the mode above): "
                                "modes in ascending order of frequency", "not ascending")
    zeta = _numbers(path, "damping_ratio", _column(path, header, data, "damping_ratio", cols))
    for i, z in enumerate(zeta):
        if not 0.0 <= z < 1.0:
            raise _error(path, f"damping_ratio[row {i + 1}]", z, "0 <= damping_ratio < 1", "out of range")
    types = tuple(_column(path, header, data, "type", cols))
    for i, t in enumerate(types):
        if t not in MODE_TYPES:
            raise _error(path, f"type[row {i + 1}]", t, ", ".join(MODE_TYPES), "unknown mode type")
    mass = _numbers(path, "modal_mass", _column(path, header, data, "modal_mass", cols))
    for i, mm in enumerate(mass):
        if abs(mm - 1.0) > MODAL_MASS_TOLERANCE:
            raise _error(
                path, f"modal_mass[row {i + 1}]", mm,
                f"1 within {MODAL_MASS_TOLERANCE:g} (phi^T M phi = 1: divide a shape by "
                "sqrt of its modal mass)", "not mass-normalised")
    return freq, zeta, types


def _shape_block(path: str, header: list[str], data: list[list[str]], n_modes: int, prefix: str = "",
                 required: bool = True) -> np.ndarray | None:
    """(n_rows, 3, n_modes) values of the columns ``<prefix>y<k>, <prefix>z<k>, <prefix>rx<k>``."""
    names = [f"{prefix}{c}{k + 1}" for k in range(n_modes) for c in COMPONENTS]
    present = [n for n in names if n in header]
    if not present and not required:
        return None
    allowed = (f"columns {prefix}y<k>, {prefix}z<k>, {prefix}rx<k> for every mode k = 1 ... {n_modes} of the "
               "modes file")
    out = np.empty((len(data), 3, n_modes))
    for k in range(n_modes):
        for c, comp in enumerate(COMPONENTS):
            name = f"{prefix}{comp}{k + 1}"
            out[:, c, k] = _numbers(path, name, _column(path, header, data, name, allowed))
    extra = [h for h in header if h not in names and h.rstrip("0123456789") in
             {f"{prefix}{c}" for c in COMPONENTS} and h[len(h.rstrip("0123456789")):]]
    if extra:
        raise _error(path, extra[0], extra[0], allowed, "a mode the modes file does not have")
    return out


def read_shapes(path: str, n_modes: int, length: float) -> RailShapeEvaluator:
    """The rail-shape evaluator of a shapes.csv (see the module's docstring) over a bridge of ``length``."""
    header, data = _rows(path)
    x = _numbers(path, "x", _column(path, header, data, "x", "a column x [m] along the track"))
    values = _shape_block(path, header, data, n_modes)
    slopes = _shape_block(path, header, data, n_modes, "d", required=False)
    for i, xi in enumerate(x):
        if not -X_TOLERANCE <= xi <= length + X_TOLERANCE:
            raise _error(path, f"x[row {i + 1}]", xi, f"0 <= x <= {length:g} m (the sum of the bridge's spans)",
                                "a station outside the bridge")
        if i and xi < x[i - 1]:
            raise _error(path, f"x[row {i + 1}]", xi, f">= {x[i - 1]:g} m: stations in order along the track",
                                "not ascending")
        if i > 1 and xi == x[i - 2]:
            raise _error(path, f"x[row {i + 1}]", xi, "each x at most twice (twice: the two sides of a support)",
                                "a station three times")
    if abs(x[0]) > X_TOLERANCE or abs(x[-1] - length) > X_TOLERANCE:
        bad = 1 if abs(x[0]) > X_TOLERANCE else len(x)
        raise _error(path, f"x[row {bad}]", float(x[bad - 1]),
                            f"stations from x = 0 to x = {length:g} m: the track line over the whole deck",
                            "the track line does not cover the deck")
    flat = values.reshape(len(x), -1)
    if slopes is None:
        slopes = _spline_slopes(x, flat).reshape(values.shape)
    d = slopes.reshape(len(x), -1)
    seg = [i for i in range(len(x) - 1) if x[i + 1] > x[i]]
    if not seg:
        raise _error(path, "x", list(x[:3]), "at least two different stations", "no length")
    n_seg = len(seg)
    coef = np.zeros((n_seg + 2, 4, 3 * n_modes))
    x_start = np.empty(n_seg)
    inv = np.empty(n_seg)
    for s, i in enumerate(seg):
        L = x[i + 1] - x[i]
        p0, p1, m0, m1 = flat[i], flat[i + 1], L * d[i], L * d[i + 1]
        coef[s + 1] = (p0, m0, -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1, 2.0 * p0 + m0 - 2.0 * p1 + m1)
        x_start[s], inv[s] = x[i], 1.0 / L
    end = max(float(x[-1]), length)
    return RailShapeEvaluator(
        bounds=np.concatenate([[-np.inf], x_start, [np.nextafter(end, np.inf)]]),
        x_start=np.concatenate([[0.0], x_start, [0.0]]),
        inv_length=np.concatenate([[0.0], inv, [0.0]]),
        coefficients=coef, length=length, n_modes=n_modes,
    )


def _spline_slopes(x: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Slopes at the stations of a not-a-knot cubic spline through each piece (pieces end at a station
    given twice); a piece of two stations is a straight line, of three the parabola through them."""
    out = np.zeros_like(values)
    cuts = [0] + [i + 1 for i in range(len(x) - 1) if x[i + 1] == x[i]] + [len(x)]
    for a, b in zip(cuts[:-1], cuts[1:]):
        if b - a >= 2:
            out[a:b] = _not_a_knot_slopes(x[a:b], values[a:b])
    return out


def _not_a_knot_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Slopes m_i of the not-a-knot cubic spline through (x_i, y_i), y of shape (n, ...): the banded
    system of C2 continuity, its end rows third-derivative continuity at x_1 and x_(n-2) (de Boor,
    A Practical Guide to Splines, ch. IV; the system scipy's CubicSpline solves)."""
    n = len(x)
    dx = np.diff(x)
    slope = np.diff(y, axis=0) / dx[:, None]
    if n == 2:
        return np.vstack([slope, slope])
    if n == 3:  # the parabola through the three points
        c = (slope[1] - slope[0]) / (x[2] - x[0])
        return np.vstack([slope[0] - c * dx[0], slope[0] + c * dx[0], slope[1] + c * dx[1]])
    ab = np.zeros((3, n))
    rhs = np.empty_like(y)
    ab[1, 1:-1] = 2.0 * (dx[:-1] + dx[1:])
    ab[0, 2:] = dx[:-1]
    ab[2, :-2] = dx[1:]
    rhs[1:-1] = 3.0 * (dx[1:, None] * slope[:-1] + dx[:-1, None] * slope[1:])
    d = x[2] - x[0]
    ab[1, 0], ab[0, 1] = dx[1], d
    rhs[0] = ((dx[0] + 2.0 * d) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / d
    d = x[-1] - x[-3]
    ab[1, -1], ab[2, -2] = dx[-2], d
    rhs[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * d + dx[-1]) * dx[-2] * slope[-1]) / d
    return solve_banded((1, 1), ab, rhs)


def read_stations(path: str, n_modes: int, spans: tuple[float, ...]) -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
    """(names, x [m] or NaN, (n, 3, n_modes) shape rows) of a stations.csv; a span station
    (``span<i>.q1``, ``.mid``, ``.q3``, whose derived channels take their position from the spans) must
    lie where the spans put it."""
    length = float(sum(spans))
    header, data = _rows(path)
    names = tuple(_column(path, header, data, "station", "a column station (names, e.g. span1.mid, pier1.top)"))
    for i, n in enumerate(names):
        if not n or any(c.isspace() for c in n) or names.index(n) != i:
            raise _error(path, f"station[row {i + 1}]", n, "a unique name without spaces, e.g. span1.mid",
                         "bad station name")
    texts = _column(path, header, data, "x", "a column x [m] along the track (empty: not on the deck, e.g. a pier top)")
    allowed = "a finite number or empty (a station not on the deck)"
    x = np.full(len(texts), math.nan)
    for i, t in enumerate(texts):
        if t:
            v = float(t) if _is_number(t) else math.nan
            if not math.isfinite(v):
                raise _error(path, f"x[row {i + 1}]", t, allowed, "not a finite number")
            x[i] = v
    at = station_positions(names, spans)
    for i, xi in enumerate(x):
        if math.isfinite(xi) and not -X_TOLERANCE <= xi <= length + X_TOLERANCE:
            raise _error(path, f"x[row {i + 1}]", xi, f"0 <= x <= {length:g} m (the sum of the bridge's spans) "
                         "or empty (a station not on the deck)", "a station outside the bridge")
        want = at.get(names[i])
        if want is not None and not abs(xi - want) <= X_TOLERANCE + 1e-9 * length:
            raise _error(path, f"x[row {i + 1}]", xi, f"{want:g} m, where the spans put {names[i]} (its derived "
                         "channels are taken there)", "a span station off its place")
    return names, x, _shape_block(path, header, data, n_modes)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _deck_stations(spans: tuple[float, ...]) -> tuple[list[str], np.ndarray]:
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    names, xs = [], []
    for s, (x0, L) in enumerate(zip(starts, spans)):
        for label, frac in (("q1", 0.25), ("mid", 0.5), ("q3", 0.75)):
            names.append(f"span{s + 1}.{label}")
            xs.append(x0 + frac * L)
    return names, np.array(xs)


def _check_spans(bridge: ModalTable) -> None:
    where = f"bridge '{bridge.name}'"
    if not bridge.spans:
        raise StructureError(where, "spans", [], "at least one span length > 0", "no spans")
    for i, span in enumerate(bridge.spans):
        if not SPAN_RANGE[0] <= span <= SPAN_RANGE[1]:
            raise StructureError(where, f"spans[{i}]", span, f"{SPAN_RANGE[0]:g} m <= span <= {SPAN_RANGE[1]:g} m",
                                 "no bridge span")


def imported_modal_bridge(bridge: ModalTable, max_frequency: float, max_modes: int = 0,
                          rayleigh: tuple[float, float] | None = None) -> ModalBridge:
    """The :class:`ModalBridge` of a ``modal_table`` bridge: the modes of its tables up to
    ``max_frequency`` [Hz] (at most ``max_modes`` if > 0); ``rayleigh`` (alpha, beta) replaces the
    tables' damping ratios as in :func:`.fe.modal_bridge`.

    Raises ScenarioError naming the table file, the column and the row for bad table data;
    StructureError (key ``max_frequency``) when no mode lies below ``max_frequency``.
    """
    _check_spans(bridge)
    where = f"bridge '{bridge.name}'"
    if not (max_frequency > 0.0 and math.isfinite(max_frequency)):
        raise StructureError(where, "max_frequency", max_frequency, "a finite frequency > 0 [Hz]")
    if max_modes < 0:
        raise StructureError(where, "max_modes", max_modes, ">= 0 (0: no limit)")
    freq, zeta, types = read_modes(bridge.modes)
    n_all = freq.size
    length = bridge.length
    tracks = tuple(TrackShapes(float(t.offset), float(t.height), read_shapes(t.shapes, n_all, length))
                   for t in bridge.tracks)
    evaluator = tracks[0].shapes if tracks else read_shapes(bridge.shapes, n_all, length)
    if bridge.stations:
        names, xs, rows = read_stations(bridge.stations, n_all, bridge.spans)
    elif len(tracks) > 1:  # the span points along each track (the girder axis is not in the tables)
        deck, xs = _deck_stations(bridge.spans)
        names, rows = track_stations(deck, xs, tracks)
    else:
        names, xs = _deck_stations(bridge.spans)
        r = evaluator(xs)
        rows = np.stack([r.y, r.z, r.rx], axis=1)
    keep = int(np.count_nonzero(freq <= max_frequency))
    if keep == 0:
        raise StructureError(where, "max_frequency", max_frequency, f"above the bridge's lowest mode, {freq[0]:.4g} Hz",
                             "no mode below max_frequency")
    if max_modes > 0:
        keep = min(keep, max_modes)
    if rayleigh is not None:
        zeta = rayleigh_damping_ratios(2.0 * np.pi * freq, *rayleigh)
    full = ModalBridge(
        frequencies=freq, damping_ratios=np.asarray(zeta, dtype=float), length=length, mode_types=types,
        station_names=tuple(names), station_shapes=np.ascontiguousarray(rows), rail_shape_function=evaluator,
        description=f"imported modes of bridge '{bridge.name}' ({Path(bridge.modes).name}, "
                    f"{', '.join(Path(t.shapes).name for t in bridge.tracks) or Path(bridge.shapes).name})",
        tracks=tracks if len(tracks) > 1 else (),
    )
    return full if keep == n_all else full.truncated(keep)


# ============================================================================================ writing


def _fmt(v: float) -> str:
    return repr(float(v))  # the shortest text that reads back as the same float


def _csv(header: list[str], rows: list[list[str]], comment: str) -> str:
    buf = io.StringIO()
    buf.write("".join(f"# {line}\n" for line in comment.splitlines()))
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def modal_tables(mb: ModalBridge, girder_x: np.ndarray, girder_length: np.ndarray,
                 evaluator: RailShapeEvaluator, station_x: dict[str, float]) -> dict[str, str]:
    """The texts of modes.csv, shapes.csv and stations.csv of a ModalBridge whose rail shapes are the
    per-element polynomials of ``evaluator`` (elements starting at ``girder_x`` with ``girder_length``):
    two rows per element, its start and its end, with the exact values and slopes of its polynomial."""
    n = mb.n_modes
    modes = [[str(k + 1), _fmt(mb.frequencies[k]), _fmt(mb.damping_ratios[k]), mb.mode_types[k], "1.0"]
             for k in range(n)]
    cols = [f"{c}{k + 1}" for k in range(n) for c in COMPONENTS]
    shape_rows = []
    for e in range(girder_x.size):
        c = evaluator.coefficients[e + 1]  # (4, 3n): after the sentinel element
        L = float(girder_length[e])
        for x, val, slope in ((girder_x[e], c[0], c[1] / L),
                              (girder_x[e] + L, c.sum(axis=0), (c[1] + 2.0 * c[2] + 3.0 * c[3]) / L)):
            v, s = val.reshape(3, n), slope.reshape(3, n)
            shape_rows.append([_fmt(x)] + [_fmt(v[ci, k]) for k in range(n) for ci in range(3)]
                              + [_fmt(s[ci, k]) for k in range(n) for ci in range(3)])
    station_rows = []
    for name, shape in zip(mb.station_names, mb.station_shapes):
        x = station_x.get(name)
        station_rows.append([name, "" if x is None else _fmt(x)]
                            + [_fmt(shape[ci, k]) for k in range(n) for ci in range(3)])
    head = f"{mb.description}; mass-normalised (phi^T M phi = 1)"
    return {
        "modes.csv": _csv(["mode", "frequency_hz", "damping_ratio", "type", "modal_mass"], modes,
                          f"{head}\nfrequency_hz [Hz], damping_ratio [-], modal_mass [-]"),
        "shapes.csv": _csv(["x"] + cols + ["d" + c for c in cols], shape_rows,
                           f"{head}\nat the track line (rail level, track centre line): x [m]; y, z [m], rx [rad] per "
                           "unit modal coordinate; d*: slopes along x [1/m]\neach girder element's start and end "
                           "(a node shared by two elements twice: the slopes of each side)"),
        "stations.csv": _csv(["station", "x"] + cols, station_rows,
                             f"{head}\noutput stations: span points on the girder axis, pier tops (x empty: not on "
                             "the deck); y, z [m], rx [rad] per unit modal coordinate"),
    }


def export_modes(bridge, out: str | Path, max_frequency: float, max_modes: int = 0, *,  # noqa: ANN001
                 overwrite: bool = False, where: str = "export_modes", key: str = "out") -> dict[str, Path]:
    """Write the FE modes of ``bridge`` (a ``simple_beam`` or ``frame``) as a ``modal_table`` bridge into the
    folder ``out``: bridge.toml (kind = "modal_table", name ``<name>_modes``, the same spans), modes.csv,
    shapes.csv (a bridge of two tracks or more: shapes_track<i>.csv per track) and stations.csv, all atomically
    as one (existing ones only with ``overwrite``;
    ``where``/``key`` name the argument in errors). Returns the written paths by file name."""

    if isinstance(bridge, ModalTable):
        raise ScenarioError(where, "bridge", bridge.name, "a simple_beam or frame bridge (its finite-element modes "
                            "are exported)", "a modal_table has no finite-element model")
    modes = bridge_modes(bridge, max_frequency, max_modes)
    mb = modal_bridge_from_modes(modes)
    model = modes.model
    girder = (np.asarray(model.girder.x_start), np.asarray(model.girder.length))
    at = station_positions(mb.station_names, bridge.spans)
    lines = track_lines(bridge)
    texts = modal_tables(mb, *girder, line_shape_evaluator(model, modes.shapes, *lines[0]), at)
    shapes: dict = {"shapes": "shapes.csv"}
    if len(lines) > 1:  # a shapes file per track: shapes_track<i>.csv
        del texts["shapes.csv"]
        shapes = {"tracks": [{"shapes": f"shapes_track{i + 1}.csv", "offset": e, "height": h}
                             for i, (e, h) in enumerate(lines)]}
        for i, (e, h) in enumerate(lines):
            texts[f"shapes_track{i + 1}.csv"] = modal_tables(
                mb, *girder, line_shape_evaluator(model, modes.shapes, e, h), at)["shapes.csv"]
    name = f"{bridge.name}_modes"
    toml = dumps_toml(
        {"kind": "modal_table", "name": name, "spans": [float(s) for s in bridge.spans], "modes": "modes.csv",
         "stations": "stations.csv", **shapes,
         "description": f"the finite-element modes of bridge '{bridge.name}' up to {max_frequency:g} Hz, imported",
         "source": f"tb-exudyn export-modes {bridge.name} (tb_exudyn.structure.imported.export_modes)"},
        f"tb_exudyn bridge '{name}': modes of '{bridge.name}' as tables (docs/modal_bridge.md)")
    folder = Path(out)
    files = ["bridge.toml", "modes.csv", *sorted(k for k in texts if k.startswith("shapes")), "stations.csv"]
    targets = output_targets(folder / files[0], sidecars=[folder / f for f in files[1:]], overwrite=overwrite,
                             where=where, key=key)
    content = {"bridge.toml": toml, **texts}
    folder.mkdir(parents=True, exist_ok=True)
    written = write_output([(t, content[f].encode("utf-8")) for t, f in zip(targets, files)], named=folder / files[0],
                           overwrite=overwrite, where=where, key=key)
    return dict(zip(files, written))


__all__ = ["MODAL_MASS_TOLERANCE", "MODE_TYPES", "export_modes", "imported_modal_bridge", "modal_tables",
           "read_modes", "read_shapes", "read_stations"]
