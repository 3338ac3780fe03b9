"""User-supplied PSD tables (CSV) as spectra.

File format: lines starting with ``#`` are comments; the first other line is a header naming the
columns (comma separated); every following non-blank line holds one number per column.
The abscissa column is ``wavelength`` [m] or ``spatial_frequency`` [rad/m] (chosen by ``x_column``);
the PSD column (default ``psd``) is one-sided in unit^2/(rad/m). Rows may come in any order.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..files import MIB, FileRefused, read_text
from .spectra import KINDS, UNITS, SpectrumError, TableSpectrum

X_COLUMNS = ("wavelength", "spatial_frequency")
#: largest spectrum table read [bytes]
MAX_TABLE_BYTES = 16 * MIB


def _parse_rows(path: Path, lines: list[str]) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header fields and numbered data rows (1-based line numbers), comments and blanks dropped."""
    header: list[str] | None = None
    rows: list[tuple[int, list[str]]] = []
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f.strip() for f in line.split(",")]
        if header is None:
            header = fields
        else:
            rows.append((lineno, fields))
    if header is None:
        raise SpectrumError(f"{path}: no header line (expected column names such as 'wavelength,psd')")
    return header, rows


def _number(path: Path, lineno: int, column: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise SpectrumError(f"{path}, line {lineno}: column {column!r}: {text!r} is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise SpectrumError(f"{path}, line {lineno}: column {column!r}: {text!r} must be finite and > 0")
    return value


def user_table_spectrum(path: str | Path, kind: str, unit: str, x_column: str = "wavelength",
                        psd_column: str = "psd", name: str | None = None) -> TableSpectrum:
    """Spectrum from a CSV table, interpolated linearly in log-log.

    Parameters
    ----------
    path : CSV file (format in the module docstring).
    kind : ``"vertical"``, ``"alignment"``, ``"cross_level"`` or ``"gauge"``.
    unit : unit of the irregularity, ``"m"`` or ``"rad"``.
    x_column : ``"wavelength"`` [m] or ``"spatial_frequency"`` [rad/m]: header name of the abscissa.
    psd_column : header name of the PSD column [unit^2/(rad/m), one-sided].
    name : spectrum name; default ``"user:<file name>"``.

    Returns
    -------
    TableSpectrum whose validity and default band are the table's frequency range.

    Raises
    ------
    SpectrumError naming the file (and line) for a missing, non-regular (FIFO, device), oversized or
    non-UTF-8 file, missing column, wrong field count, non-numeric, non-finite or non-positive value,
    duplicate abscissa, or fewer than two rows.
    """
    path = Path(path)
    if x_column not in X_COLUMNS:
        raise SpectrumError(f"x_column must be one of {X_COLUMNS}, got {x_column!r}")
    if kind not in KINDS or unit not in UNITS:
        raise SpectrumError(f"{path}: kind must be one of {KINDS} and unit one of {UNITS}, got {kind!r}, {unit!r}")
    try:
        lines = read_text(path, max_bytes=MAX_TABLE_BYTES, follow_symlinks=True).splitlines()
    except FileNotFoundError:
        raise SpectrumError(f"{path}: cannot read spectrum table (file not found)") from None
    except FileRefused as exc:
        raise SpectrumError(f"{path}: cannot read spectrum table: it {exc}") from None
    header, rows = _parse_rows(path, lines)
    for col in (x_column, psd_column):
        if col not in header:
            raise SpectrumError(f"{path}: header {','.join(header)!r} has no column {col!r}")
    ix, ip = header.index(x_column), header.index(psd_column)
    xs, ps = [], []
    for lineno, fields in rows:
        if len(fields) != len(header):
            raise SpectrumError(f"{path}, line {lineno}: {len(fields)} fields, header has {len(header)}")
        xs.append(_number(path, lineno, x_column, fields[ix]))
        ps.append(_number(path, lineno, psd_column, fields[ip]))
    if len(xs) < 2:
        raise SpectrumError(f"{path}: needs at least two data rows, found {len(xs)}")
    omega = 2 * math.pi / np.asarray(xs) if x_column == "wavelength" else np.asarray(xs)
    order = np.argsort(omega)
    omega, values = omega[order], np.asarray(ps)[order]
    if np.any(np.diff(omega) <= 0):
        dup = rows[int(order[int(np.argmax(np.diff(omega) <= 0)) + 1])][0]
        raise SpectrumError(f"{path}, line {dup}: duplicate {x_column} value")
    band = (float(omega[0]), float(omega[-1]))
    return TableSpectrum(name=name or f"user:{path.name}", kind=kind, unit=unit,
                         source=f"user table {path}", default_band=band, validity=band,
                         omega=tuple(map(float, omega)), values=tuple(map(float, values)))
