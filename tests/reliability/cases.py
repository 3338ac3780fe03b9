"""Hostile inputs of issue 15 as data: each case builds its files in a scratch folder and says how
to run it (a ``tb-exudyn`` command line or a Python call) and what the one-line error must name.

Shared by the tests (tests/reliability/test_cases.py, in this process) and by the measurement of
the issue's table (tests/reliability/measure.py, one subprocess per case against any checkout).
Every case here must end in exit status 2 with one line naming the file (or "command line" and the
option, or the environment variable), no traceback, and nothing written anywhere.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable

import numpy as np

CHANNELS = ("bridge.span1.mid.disp_z", "car1.body.acc_z")
UNITS = ("m", "m/s^2")
NT = 51


@dataclass(frozen=True)
class Run:
    """How to run a case: ``argv`` for ``tb-exudyn`` or ``code`` for Python (``code`` raises the
    error; the runner maps a UserError or SpectrumError to exit 2, as the CLI does)."""

    argv: tuple[str, ...] = ()
    code: str = ""
    expect: tuple[str, ...] = ()
    env: dict[str, str] = field(default_factory=dict)
    #: may block or allocate without bound if the defence fails: run in a subprocess with limits
    isolate: bool = False


@dataclass(frozen=True)
class Case:
    id: str
    group: str
    build: Callable[[Path], Run]


# ------------------------------------------------------------------------------------ result files
@lru_cache(maxsize=1)
def scenario_toml() -> str:
    from tb_exudyn.scenario import load_scenario, scenario_to_toml

    return scenario_to_toml(load_scenario("quick"))


def th_arrays(nc: int = 2, nt: int = NT, value: float = 1.0) -> dict[str, np.ndarray]:
    return {"time": np.arange(nt) * 0.01, "values": np.full((nc, nt), value)}


def th_meta(**over: Any) -> dict[str, Any]:
    meta = {"format": "tb_exudyn.time_history/1", "channels": list(CHANNELS), "units": list(UNITS),
            "provenance": {"engine": "test"}, "scenario_toml": None}
    meta.update(over)
    return meta


def rr_arrays(nc: int = 2, nt: int = NT, nf: int = 3) -> dict[str, np.ndarray]:
    return {"time": np.arange(nt) * 0.01, "mean": np.zeros((nc, nt)), "std": np.ones((nc, nt)),
            "freq": 1.0 + np.arange(nf), "df": np.ones(nf), "psd": np.full((nc, nf, nt), 1.0 / nf)}


def rr_meta(**over: Any) -> dict[str, Any]:
    meta = {"format": "tb_exudyn.random_response/1", "method": "pem", "channels": list(CHANNELS),
            "units": list(UNITS), "band_hz": [0.5, 3.5], "types": ["german_low.vertical"], "n_samples": 0,
            "provenance": {"engine": "test"}, "scenario_toml": scenario_toml()}
    meta.update(over)
    return meta


def write_result(folder: Path, arrays: dict[str, np.ndarray] | bytes | None, meta: dict | str | bytes | None) -> Path:
    """A result folder holding the given arrays (np.savez) and meta (JSON, or raw text/bytes)."""
    folder.mkdir(parents=True, exist_ok=True)
    if isinstance(arrays, bytes):
        (folder / "arrays.npz").write_bytes(arrays)
    elif arrays is not None:
        np.savez(folder / "arrays.npz", **arrays)
    if isinstance(meta, dict):
        (folder / "meta.json").write_text(json.dumps(meta))
    elif isinstance(meta, str):
        (folder / "meta.json").write_text(meta)
    elif isinstance(meta, bytes):
        (folder / "meta.json").write_bytes(meta)
    return folder


def npz_bytes(members: dict[str, bytes], compression: int = zipfile.ZIP_STORED) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression) as zf:
        for name, data in members.items():
            zf.writestr(name, data)
    return buf.getvalue()


def npy_bytes(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array(buf, a, allow_pickle=True)
    return buf.getvalue()


def npy_declaring(shape: tuple[int, ...], data: bytes = b"\0" * 8, descr: str = "<f8") -> bytes:
    """An npy member whose header declares ``shape`` but which holds only ``data``."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": descr, "fortran_order": False, "shape": shape})
    return buf.getvalue() + data


def th_npz(**replace: bytes) -> bytes:
    members = {f"{k}.npy": npy_bytes(v) for k, v in th_arrays().items()}
    members.update({f"{k}.npy": v for k, v in replace.items()})
    return npz_bytes(members)


def report(folder: Path, *more: str) -> tuple[str, ...]:
    return ("report", str(folder), *more)


def plot(folder: Path) -> tuple[str, ...]:
    return ("plot", str(folder))


def _load(folder: Path) -> str:
    return f"from tb_exudyn.results import load_results; load_results({str(folder)!r})"


def _good_th(d: Path) -> Path:
    return write_result(d / "det", th_arrays(), th_meta())


# each builder returns a Run; d is an empty scratch folder
def _symlink_meta_dev_zero(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), None)
    os.symlink("/dev/zero", f / "meta.json")
    return Run(argv=report(f), expect=(str(f / "meta.json"), "symbolic link"), isolate=True)


def _symlink_arrays_dev_zero(d: Path) -> Run:
    f = write_result(d / "det", None, th_meta())
    os.symlink("/dev/zero", f / "arrays.npz")
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "symbolic link"), isolate=True)


def _fifo_meta(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), None)
    os.mkfifo(f / "meta.json")
    return Run(argv=report(f), expect=(str(f / "meta.json"), "FIFO"), isolate=True)


def _fifo_arrays(d: Path) -> Run:
    f = write_result(d / "det", None, th_meta())
    os.mkfifo(f / "arrays.npz")
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "FIFO"), isolate=True)


def _symlink_meta_outside(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), None)
    (d / "elsewhere.json").write_text(json.dumps(th_meta()))
    os.symlink(d / "elsewhere.json", f / "meta.json")
    return Run(argv=report(f), expect=(str(f / "meta.json"), "symbolic link"))


def _symlink_arrays_outside(d: Path) -> Run:
    f = write_result(d / "det", None, th_meta())
    np.savez(d / "elsewhere.npz", **th_arrays())
    os.symlink(d / "elsewhere.npz", f / "arrays.npz")
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "symbolic link"))


def _symlinked_figures(d: Path) -> Run:
    f = _good_th(d)
    (d / "victim").mkdir()
    os.symlink(d / "victim", f / "figures")
    return Run(argv=plot(f), expect=(str(f / "figures"), "symbolic link"))


def _symlinked_result_subfolder(d: Path) -> Run:
    _good_th(d / "real")
    (d / "out").mkdir()
    os.symlink(d / "real" / "det", d / "out" / "det")
    return Run(argv=report(d / "out"), expect=(str(d / "out" / "det"), "symbolic link"))


def _object_array(d: Path) -> Run:
    f = write_result(d / "det", th_npz(values=npy_bytes(np.array([[1, "x"]] * 2, dtype=object))), th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'values'", "object"))


def _huge_declared_shape(d: Path) -> Run:
    f = write_result(d / "det", th_npz(time=npy_declaring((10 ** 12,))), th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'time'", "1000000000000"), isolate=True)


def _huge_declared_psd(d: Path) -> Run:
    members = {f"{k}.npy": npy_bytes(v) for k, v in rr_arrays().items()}
    members["psd.npy"] = npy_declaring((2, 3 * 10 ** 9, NT))
    f = write_result(d / "pem", npz_bytes(members), rr_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'psd'"), isolate=True)


def _structured_dtype(d: Path) -> Run:
    rec = np.zeros(NT, dtype=[("a", "<f8"), ("b", "<i4")])
    f = write_result(d / "det", th_npz(time=npy_bytes(rec)), th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'time'", "dtype"))


def _compressed_npz(d: Path) -> Run:
    f = write_result(d / "det", None, th_meta())
    np.savez_compressed(f / "arrays.npz", **th_arrays())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "compressed"))


def _unexpected_member(d: Path) -> Run:
    arrays = {**th_arrays(), "extra": np.zeros(3)}
    f = write_result(d / "det", arrays, th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'extra'"))


def _missing_member(d: Path) -> Run:
    arrays = rr_arrays()
    del arrays["std"]
    f = write_result(d / "pem", arrays, rr_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'std'"))


def _truncated_npz(d: Path) -> Run:
    data = th_npz()
    f = write_result(d / "det", data[: len(data) // 2], th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"),))


def _flipped_byte(d: Path) -> Run:
    data = bytearray(th_npz())
    i = data.index(npy_bytes(th_arrays()["values"])[-200:])  # inside the values' data
    data[i + 100] ^= 0x40
    f = write_result(d / "det", bytes(data), th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'values'"))


def _npz_not_zip(d: Path) -> Run:
    f = write_result(d / "det", b"this is not a zip file\n" * 10, th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "zip"))


def _npz_empty(d: Path) -> Run:
    f = write_result(d / "det", b"", th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"),))


def _meta_missing(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), None)
    return Run(code=_load(f), expect=(str(f / "meta.json"), "not found"))


def _arrays_missing(d: Path) -> Run:
    f = write_result(d / "det", None, th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "not found"))


def _meta_bad_json(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), '{"format": "tb_exudyn.time_history/1", ')
    return Run(argv=report(f), expect=(str(f / "meta.json"), "JSON"))


def _meta_not_utf8(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), json.dumps(th_meta()).encode().replace(b"test", b"t\xffst"))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "UTF-8"))


def _meta_very_deep(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), '{"format": "tb_exudyn.time_history/1", "x": ' + "[" * 200_000
                     + "]" * 200_000 + "}")
    return Run(argv=report(f), expect=(str(f / "meta.json"), "deep"))


def _meta_deep(d: Path) -> Run:
    nested: Any = 0
    for _ in range(100):
        nested = [nested]
    f = write_result(d / "det", th_arrays(), th_meta(provenance={"x": nested}))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "deep"))


def _meta_huge(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), None)
    with open(f / "meta.json", "wb") as fh:  # sparse: 64 MiB of zeros without writing them
        fh.truncate(64 * 1024 * 1024)
    return Run(argv=report(f), expect=(str(f / "meta.json"), "MiB"), isolate=True)


def _meta_list(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), "[1, 2, 3]")
    return Run(argv=report(f), expect=(str(f / "meta.json"), "object"))


def _missing_channels(d: Path) -> Run:
    meta = th_meta()
    del meta["channels"]
    f = write_result(d / "det", th_arrays(), meta)
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'channels'", "missing"))


def _missing_units_rr(d: Path) -> Run:
    meta = rr_meta()
    del meta["units"]
    f = write_result(d / "pem", rr_arrays(), meta)
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'units'", "missing"))


def _missing_format(d: Path) -> Run:
    meta = th_meta()
    del meta["format"]
    f = write_result(d / "det", th_arrays(), meta)
    return Run(code=_load(f), expect=(str(f / "meta.json"), "'format'"))


def _channels_wrong_type(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(channels="bridge.span1.mid.disp_z"))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'channels'"))


def _two_channels_51_rows(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(nc=51), th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'values'", "channels"))


def _two_channels_51_rows_rr(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(nc=51), rr_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'mean'", "channels"))


def _units_mismatch(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(units=["m"]))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'units'"))


def _channel_traversal(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(channels=["bridge/../../../escape", "car1.body.acc_z"]))
    return Run(argv=plot(f), expect=(str(f / "meta.json"), "channels[0]"))


def _channel_dotdot(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), rr_meta(channels=["..", "car1.body.acc_z"]))
    return Run(argv=plot(f), expect=(str(f / "meta.json"), "channels[0]"))


def _duplicate_channels(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(channels=["car1.body.acc_z", "car1.body.acc_z"]))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'channels'", "repeated"))


def _unknown_format(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(format="tb_exudyn.time_history/99"))
    return Run(code=_load(f), expect=(str(f / "meta.json"), "'format'"))


def _unknown_method(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), rr_meta(method="guess"))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'method'"))


def _band_nan(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), json.dumps(rr_meta(band_hz=[float("nan"), 3.5])))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'band_hz'"))


def _band_inverted(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), rr_meta(band_hz=[3.5, 0.5]))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'band_hz'"))


def _n_samples_text(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), rr_meta(n_samples="many"))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "'n_samples'"))


def _samples_mismatch(d: Path) -> Run:
    arrays = {**rr_arrays(), "samples": np.zeros((3, 2, NT))}
    f = write_result(d / "mc", arrays, rr_meta(method="monte_carlo", n_samples=5))
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'samples'", "n_samples"))


def _scenario_bad_toml(d: Path) -> Run:
    f = write_result(d / "pem", rr_arrays(), rr_meta(scenario_toml="name = [unclosed"))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "scenario_toml"))


def _scenario_bad_value(d: Path) -> Run:
    text = scenario_toml().replace("speed_kmh = 250.0", "speed_kmh = -250.0")
    assert text != scenario_toml()
    f = write_result(d / "pem", rr_arrays(), rr_meta(scenario_toml=text))
    return Run(argv=report(f), expect=(str(f / "meta.json"), "speed_kmh"))


def _scenario_names_a_file(d: Path) -> Run:
    (d / "secret.toml").write_text('kind = "sprung_mass"\n')
    text = 'name = "x"\nspeed_kmh = 100.0\nbridge = "../secret.toml"\n[train]\nvehicles = ["../secret.toml"]\n'
    f = write_result(d / "pem", rr_arrays(), rr_meta(scenario_toml=text))
    return Run(argv=report(f), expect=(str(f / "meta.json"),))


def _nan_in_std(d: Path) -> Run:
    arrays = rr_arrays()
    arrays["std"][1, 7] = np.nan
    f = write_result(d / "pem", arrays, rr_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'std'", "non-finite"))


def _time_not_increasing(d: Path) -> Run:
    arrays = th_arrays()
    arrays["time"][10] = 0.0
    f = write_result(d / "det", arrays, th_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'time'", "increasing"))


def _mean_vs_time(d: Path) -> Run:
    arrays = rr_arrays()
    arrays["mean"] = np.zeros((2, NT - 1))
    f = write_result(d / "pem", arrays, rr_meta())
    return Run(argv=report(f), expect=(str(f / "arrays.npz"), "'mean'"))


def _folder_missing(d: Path) -> Run:
    return Run(argv=report(d / "nothing"), expect=(str(d / "nothing"),))


def _folder_is_file(d: Path) -> Run:
    (d / "afile").write_text("x")
    return Run(code=_load(d / "afile"), expect=(str(d / "afile"), "not a folder"))


def _one_bad_among_good(d: Path) -> Run:
    _good_th(d / "out")
    write_result(d / "out" / "pem", rr_arrays(nc=3), rr_meta())
    return Run(argv=report(d / "out"), expect=(str(d / "out" / "pem" / "arrays.npz"), "'mean'"))


def _empty_folder(d: Path) -> Run:
    (d / "empty").mkdir()
    return Run(argv=report(d / "empty"), expect=(str(d / "empty"), "no tb_exudyn result"))


# ------------------------------------------------------------------------------------ scenario files
def _scenario_not_utf8(d: Path) -> Run:
    p = d / "bad.toml"
    p.write_bytes(b'name = "caf\xe9"\nspeed_kmh = 100.0\n')
    return Run(argv=("show", str(p)), expect=(str(p), "UTF-8"))


def _scenario_binary(d: Path) -> Run:
    p = d / "binary.toml"
    p.write_bytes(bytes(np.random.default_rng(5).integers(0, 256, 4096, dtype=np.uint8)))
    return Run(argv=("run", str(p), "--out", str(d / "out"), "--no-figures"), expect=(str(p),))


def _scenario_fifo(d: Path) -> Run:
    p = d / "fifo.toml"
    os.mkfifo(p)
    return Run(argv=("show", str(p)), expect=(str(p), "FIFO"), isolate=True)


def _scenario_dev_zero(d: Path) -> Run:
    p = d / "zero.toml"
    os.symlink("/dev/zero", p)
    return Run(argv=("show", str(p)), expect=(str(p), "device"), isolate=True)


def _scenario_directory(d: Path) -> Run:
    p = d / "adir.toml"
    p.mkdir()
    return Run(argv=("show", str(p)), expect=(str(p), "directory"))


def _scenario_deep(d: Path) -> Run:
    p = d / "deep.toml"
    p.write_text("x = " + "[" * 100_000 + "]" * 100_000 + "\n")
    return Run(argv=("show", str(p)), expect=(str(p),))


def _vehicle_not_utf8(d: Path) -> Run:
    (d / "car.toml").write_bytes(b'kind = "moving_force"\nname = "\xff"\nforce = 1.0\nlength = 1.0\n')
    p = d / "sc.toml"
    p.write_text('name = "x"\nspeed_kmh = 100.0\nbridge = "single_span_32m"\n[train]\nvehicles = ["car.toml"]\n')
    return Run(argv=("show", str(p)), expect=(str(d / "car.toml"), "UTF-8"))


# ------------------------------------------------------------------------------------ spectrum tables
def _csv(d: Path, data: bytes, name: str = "psd.csv") -> tuple[Path, str]:
    p = d / name
    p.write_bytes(data)
    return p, f"from tb_exudyn.track import user_table_spectrum; user_table_spectrum({str(p)!r}, 'vertical', 'm')"


def _csv_not_utf8(d: Path) -> Run:
    p, code = _csv(d, b"# PSD \xb5m\nwavelength,psd\n10,1e-6\n5,1e-7\n")
    return Run(code=code, expect=(str(p), "UTF-8"))


def _csv_binary(d: Path) -> Run:
    p, code = _csv(d, bytes(range(256)) * 4)
    return Run(code=code, expect=(str(p),))


def _csv_malformed(d: Path) -> Run:
    p, code = _csv(d, b"wavelength,psd\n10,1e-6\n5\n2,1e-8\n")
    return Run(code=code, expect=(str(p), "line 3"))


def _csv_nan(d: Path) -> Run:
    p, code = _csv(d, b"wavelength,psd\n10,1e-6\n5,nan\n2,1e-8\n")
    return Run(code=code, expect=(str(p), "line 3", "nan"))


def _csv_duplicate(d: Path) -> Run:
    p, code = _csv(d, b"wavelength,psd\n10,1e-6\n5,1e-7\n10,1e-8\n")
    return Run(code=code, expect=(str(p), "duplicate"))


def _csv_fifo(d: Path) -> Run:
    p = d / "fifo.csv"
    os.mkfifo(p)
    code = f"from tb_exudyn.track import user_table_spectrum; user_table_spectrum({str(p)!r}, 'vertical', 'm')"
    return Run(code=code, expect=(str(p), "FIFO"), isolate=True)


# ------------------------------------------------------------------------------------ environment, CLI
def _models_missing(d: Path) -> Run:
    return Run(argv=("list",), env={"TB_EXUDYN_MODELS": str(d / "nowhere")}, expect=("TB_EXUDYN_MODELS",))


def _models_is_file(d: Path) -> Run:
    (d / "models.txt").write_text("x")
    return Run(argv=("show", "quick"), env={"TB_EXUDYN_MODELS": str(d / "models.txt")}, expect=("TB_EXUDYN_MODELS",))


def _models_empty_folder(d: Path) -> Run:
    (d / "models").mkdir()
    return Run(argv=("list",), env={"TB_EXUDYN_MODELS": str(d / "models")}, expect=("TB_EXUDYN_MODELS",))


def _out_empty(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "det", "--out", "", "--no-figures"), expect=("command line", "'--out'"))


def _samples_one(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "mc", "--samples", "1", "--out", str(d / "o"), "--no-figures"),
               expect=("command line", "'--samples'"))


def _samples_float(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "mc", "--samples", "1e9", "--out", str(d / "o"), "--no-figures"),
               expect=("command line", "'--samples'"))


def _seed_negative(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "mc", "--seed", "-1", "--samples", "4", "--out", str(d / "o"),
                     "--no-figures"), expect=("command line", "'--seed'"))


def _workers_zero(d: Path) -> Run:
    return Run(argv=("run", "quick", "--workers", "0", "--out", str(d / "o"), "--no-figures"),
               expect=("command line", "'--workers'"))


def _linearization_exudyn(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "mc", "--engine", "exudyn", "--samples", "4", "--linearization", "static",
                     "--out", str(d / "o"), "--no-figures"), expect=("command line", "'--linearization'"))


def _plot_empty_path(d: Path) -> Run:
    return Run(argv=("plot", ""), expect=("command line",))


CASES: list[Case] = [
    Case("meta.json -> /dev/zero", "results", _symlink_meta_dev_zero),
    Case("arrays.npz -> /dev/zero", "results", _symlink_arrays_dev_zero),
    Case("meta.json is a FIFO", "results", _fifo_meta),
    Case("arrays.npz is a FIFO", "results", _fifo_arrays),
    Case("meta.json symlink out of DIR", "results", _symlink_meta_outside),
    Case("arrays.npz symlink out of DIR", "results", _symlink_arrays_outside),
    Case("symlinked figures folder", "results", _symlinked_figures),
    Case("symlinked result sub-folder", "results", _symlinked_result_subfolder),
    Case("object array", "results", _object_array),
    Case("huge declared shape", "results", _huge_declared_shape),
    Case("huge declared PSD map", "results", _huge_declared_psd),
    Case("structured dtype", "results", _structured_dtype),
    Case("compressed npz", "results", _compressed_npz),
    Case("unexpected array", "results", _unexpected_member),
    Case("missing array", "results", _missing_member),
    Case("truncated arrays.npz", "results", _truncated_npz),
    Case("flipped byte in arrays.npz", "results", _flipped_byte),
    Case("arrays.npz not a zip", "results", _npz_not_zip),
    Case("arrays.npz empty", "results", _npz_empty),
    Case("meta.json missing", "results", _meta_missing),
    Case("arrays.npz missing", "results", _arrays_missing),
    Case("meta.json malformed", "results", _meta_bad_json),
    Case("meta.json not UTF-8", "results", _meta_not_utf8),
    Case("meta.json 200000 deep", "results", _meta_very_deep),
    Case("meta.json 100 deep", "results", _meta_deep),
    Case("meta.json 64 MiB", "results", _meta_huge),
    Case("meta.json a list", "results", _meta_list),
    Case("missing key channels", "results", _missing_channels),
    Case("missing key units", "results", _missing_units_rr),
    Case("missing key format", "results", _missing_format),
    Case("channels not a list", "results", _channels_wrong_type),
    Case("2 channels over 51 rows (history)", "results", _two_channels_51_rows),
    Case("2 channels over 51 rows (response)", "results", _two_channels_51_rows_rr),
    Case("units do not match channels", "results", _units_mismatch),
    Case("channel name with /../", "results", _channel_traversal),
    Case("channel name ..", "results", _channel_dotdot),
    Case("duplicate channel names", "results", _duplicate_channels),
    Case("unknown format version", "results", _unknown_format),
    Case("unknown method", "results", _unknown_method),
    Case("band NaN", "results", _band_nan),
    Case("band inverted", "results", _band_inverted),
    Case("n_samples not a number", "results", _n_samples_text),
    Case("samples do not match n_samples", "results", _samples_mismatch),
    Case("scenario_toml malformed", "results", _scenario_bad_toml),
    Case("scenario_toml bad value", "results", _scenario_bad_value),
    Case("scenario_toml names files", "results", _scenario_names_a_file),
    Case("NaN in std", "results", _nan_in_std),
    Case("time not increasing", "results", _time_not_increasing),
    Case("mean shorter than time", "results", _mean_vs_time),
    Case("results folder missing", "results", _folder_missing),
    Case("results folder is a file", "results", _folder_is_file),
    Case("one damaged result among good ones", "results", _one_bad_among_good),
    Case("empty results folder", "results", _empty_folder),
    Case("scenario not UTF-8", "scenario", _scenario_not_utf8),
    Case("scenario binary (run)", "scenario", _scenario_binary),
    Case("scenario is a FIFO", "scenario", _scenario_fifo),
    Case("scenario -> /dev/zero", "scenario", _scenario_dev_zero),
    Case("scenario is a directory", "scenario", _scenario_directory),
    Case("scenario nested 100000 deep", "scenario", _scenario_deep),
    Case("vehicle file not UTF-8", "scenario", _vehicle_not_utf8),
    Case("spectrum CSV not UTF-8", "csv", _csv_not_utf8),
    Case("spectrum CSV binary", "csv", _csv_binary),
    Case("spectrum CSV short row", "csv", _csv_malformed),
    Case("spectrum CSV NaN", "csv", _csv_nan),
    Case("spectrum CSV duplicate wavelength", "csv", _csv_duplicate),
    Case("spectrum CSV is a FIFO", "csv", _csv_fifo),
    Case("TB_EXUDYN_MODELS missing folder", "environment", _models_missing),
    Case("TB_EXUDYN_MODELS a file", "environment", _models_is_file),
    Case("TB_EXUDYN_MODELS empty folder", "environment", _models_empty_folder),
    Case("--out ''", "command line", _out_empty),
    Case("--samples 1", "command line", _samples_one),
    Case("--samples 1e9", "command line", _samples_float),
    Case("--seed -1", "command line", _seed_negative),
    Case("--workers 0", "command line", _workers_zero),
    Case("--linearization with --engine exudyn", "command line", _linearization_exudyn),
    Case("plot ''", "command line", _plot_empty_path),
]

#: the wrapper a Python case runs in (the CLI's mapping: a user error is one line and exit 2)
PYTHON_WRAPPER = """
import sys
from tb_exudyn.errors import UserError
from tb_exudyn.track import SpectrumError
try:
    exec(compile(sys.argv[1], "<case>", "exec"))
except (UserError, SpectrumError) as exc:
    print(f"error: {exc}", file=sys.stderr)
    sys.exit(2)
"""

#: the wrapper of an isolated case: 2 GB of address space, then the command line or the Python case
LIMITED = """
import resource, sys
resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
if sys.argv[1] == "cli":
    from tb_exudyn.cli import main
    sys.exit(main(sys.argv[2:]))
exec(compile(WRAPPER, "<wrapper>", "exec"))  # sys.argv[1] is the Python case
""".replace("WRAPPER", repr(PYTHON_WRAPPER))


def subprocess_command(run: Run, python: str) -> list[str]:
    """The command that runs a case in its own process (limited in memory)."""
    if run.argv:
        return [python, "-c", LIMITED, "cli", *run.argv]
    return [python, "-c", LIMITED, run.code]


def snapshot(root: Path) -> dict[str, tuple[int, int, int]]:
    """Every entry under ``root`` (not following links, not reading anything): mode, size, mtime."""
    out = {}
    for dirpath, dirnames, filenames in os.walk(root, followlinks=False):
        for name in dirnames + filenames:
            p = os.path.join(dirpath, name)
            st = os.lstat(p)
            out[os.path.relpath(p, root)] = (st.st_mode, st.st_size, st.st_mtime_ns)
    return out
