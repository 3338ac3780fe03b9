"""Impossible results of issue 27 as data (group "results"): values no analysis produces, provenance
fields of the wrong type, a save of a result mutated in Python, and ``plot --channels`` matching
nothing. Each must end in exit status 2 with one line naming the file (or the option) and the key,
no traceback, and nothing written, moved or deleted (tests/reliability/test_results_validation.py).

The results are the small hand-made ones of cases.py (two channels, 51 output times, three
frequencies 1, 2, 3 Hz with band [0.5, 3.5] Hz, the 'quick' scenario): each case changes one thing.
The band limit of the quick scenario is max(0.1 / time_step, speed / wavelength_min) = 100 Hz
(time_step 1e-3 s; 250 km/h over 1 m is 69.4 Hz), which the band cases quote.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .cases import NT, Case, Run, plot, report, rr_arrays, rr_meta, th_arrays, th_meta, write_result


def _rr(d: Path, name: str = "pem", arrays: dict[str, np.ndarray] | None = None, **meta: Any) -> Path:
    return write_result(d / name, rr_arrays() if arrays is None else arrays, rr_meta(**meta))


def _with(**changes: Any) -> dict[str, np.ndarray]:
    arrays = rr_arrays()
    arrays.update(changes)
    return arrays


def _npz(f: Path) -> str:
    return str(f / "arrays.npz")


def _meta(f: Path) -> str:
    return str(f / "meta.json")


# ------------------------------------------------------------------ values no analysis produces
def _negative_std(d: Path) -> Run:
    arrays = rr_arrays()
    arrays["std"][0, 5] = -1.0
    f = _rr(d, arrays=arrays)
    return Run(argv=report(f), expect=(_npz(f), "'std'", "negative", ">= 0"))


def _negative_psd(d: Path) -> Run:
    arrays = rr_arrays()
    arrays["psd"][1, 2, 3] = -1e-3
    f = _rr(d, arrays=arrays)
    return Run(argv=plot(f), expect=(_npz(f), "'psd'", "negative"))


def _negative_df(d: Path) -> Run:
    f = _rr(d, arrays=_with(df=np.array([1.0, -1.0, 1.0])))
    return Run(argv=report(f), expect=(_npz(f), "'df'", "negative"))


def _negative_freq(d: Path) -> Run:
    f = _rr(d, arrays=_with(freq=np.array([-1.0, 0.0, 1.0])), band_hz=[0.0, 3.5])
    return Run(argv=report(f), expect=(_npz(f), "'freq'", "negative"))


def _negative_var_by_type(d: Path) -> Run:
    f = _rr(d, arrays=_with(var_by_type=-np.ones((1, 2, NT))))
    return Run(argv=report(f), expect=(_npz(f), "'var_by_type'", "negative"))


def _negative_std_ci(d: Path) -> Run:
    f = _rr(d, arrays=_with(std_ci=np.stack([-np.ones((2, NT)), np.ones((2, NT))])))
    return Run(argv=report(f), expect=(_npz(f), "'std_ci'", "negative"))


def _negative_std_rate(d: Path) -> Run:
    f = _rr(d, arrays=_with(std_rate=-np.ones((2, NT))))
    return Run(argv=report(f), expect=(_npz(f), "'std_rate'", "negative"))


def _band_1e308(d: Path) -> Run:
    f = _rr(d, band_hz=[0.5, 1e308])
    return Run(argv=report(f), expect=(_meta(f), "'band_hz'", "1e+308", "f_high <= max(0.1/time_step = 100 Hz"))


def _band_above_scenario(d: Path) -> Run:
    f = _rr(d, band_hz=[0.5, 150.0])
    return Run(argv=report(f), expect=(_meta(f), "'band_hz'", "150"))


def _freq_outside_band(d: Path) -> Run:
    f = _rr(d, band_hz=[0.5, 2.5])
    return Run(argv=report(f), expect=(_npz(f), "'freq'", "band_hz"))


def _mean_1e300(d: Path) -> Run:
    f = _rr(d, arrays=_with(mean=np.full((2, NT), 1e300)))
    return Run(argv=report(f), expect=(_npz(f), "'mean'", "magnitude", "1e+100"))


def _psd_1e250(d: Path) -> Run:
    f = _rr(d, arrays=_with(psd=np.full((2, 3, NT), 1e250)))
    return Run(argv=report(f), expect=(_npz(f), "'psd'", "1e+200"))


def _th_values_1e300(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(value=1e300), th_meta())
    return Run(argv=plot(f), expect=(_npz(f), "'values'", "magnitude"))


def _one_output_time(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(nt=1), th_meta())
    return Run(argv=report(f), expect=(_npz(f), "'time'", "at least 2"))


def _no_channel(d: Path) -> Run:
    arrays = {k: (v[:0] if v.ndim > 1 and v.shape[0] == 2 else v) for k, v in rr_arrays().items()}
    arrays["psd"] = np.zeros((0, 3, NT))
    f = _rr(d, arrays=arrays, channels=[], units=[])
    return Run(argv=report(f), expect=(_meta(f), "'channels'", "no channel"))


def _psd_without_freq(d: Path) -> Run:
    f = _rr(d, arrays=_with(freq=np.zeros(0), df=np.zeros(0), psd=np.zeros((2, 0, NT))))
    return Run(argv=plot(f), expect=(_npz(f), "'psd'", "no frequency"))


def _export_negative_std(d: Path) -> Run:
    """The finding: an impossible result exported with exit 0; now refused before the file is written."""
    arrays = rr_arrays()
    arrays["std"] *= -1.0
    f = _rr(d, arrays=arrays)
    return Run(argv=("export", str(f), "--format", "csv", "--output", str(d / "out.csv")),
               expect=(_npz(f), "'std'", "negative"))


# ------------------------------------------------------------------ provenance of the wrong type
def _provenance(d: Path, **fields: Any) -> Path:
    return _rr(d, provenance={"engine": "test", **fields})


def _warnings_text(d: Path) -> Run:
    f = _provenance(d, warnings="the grid is too coarse")
    return Run(argv=report(f), expect=(_meta(f), "'provenance.warnings'", "a list of strings"))


def _warnings_of_numbers(d: Path) -> Run:
    f = _provenance(d, warnings=[1, 2])
    return Run(argv=report(f), expect=(_meta(f), "'provenance.warnings'"))


def _warnings_th(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta(provenance={"warnings": {"a": 1}}))
    return Run(argv=report(f), expect=(_meta(f), "'provenance.warnings'"))


def _damped_modes_extra_field(d: Path) -> Run:
    f = _provenance(d, damped_modes=[{"frequency": 1.0, "damping_ratio": 0.02, "label": "bridge", "colour": "red"}])
    return Run(argv=report(f), expect=(_meta(f), "'provenance.damped_modes'", "warning) only"))


def _damped_modes_text_frequency(d: Path) -> Run:
    f = _provenance(d, damped_modes=[{"frequency": "1 Hz", "damping_ratio": 0.02, "label": "bridge"}])
    return Run(argv=report(f), expect=(_meta(f), "'provenance.damped_modes'"))


def _damping_warning_text_frequency(d: Path) -> Run:
    f = _provenance(d, damping_warnings=[{"channels": ["car1.*"], "frequency": "8 Hz", "damping_ratio": 1e-4,
                                          "decay_time": 190.0, "growth_on_bridge": 0.27, "label": "bogie yaw"}])
    return Run(argv=report(f), expect=(_meta(f), "'provenance.damping_warnings'"))


def _grid_error_text_entry(d: Path) -> Run:
    f = _provenance(d, grid_error={"channels": {"car1.body.acc_z": {"rel_error_max_sigma": "large"}}})
    return Run(argv=report(f), expect=(_meta(f), "'provenance.grid_error'"))


def _derived_channels_list(d: Path) -> Run:
    f = _provenance(d, derived_channels={"channels": ["car1.body.sperling_z"]})
    return Run(argv=report(f), expect=(_meta(f), "'provenance.derived_channels'"))


def _loss_of_contact_text(d: Path) -> Run:
    f = _rr(d, "mc", method="monte_carlo", provenance={"samples_with_loss_of_contact": "some"})
    return Run(argv=report(f), expect=(_meta(f), "'provenance.samples_with_loss_of_contact'"))


# ------------------------------------------------------------------ plot --channels matching nothing
def _plot_no_match(d: Path) -> Run:
    f = _rr(d)
    return Run(argv=(*plot(f), "--channels", "nomatch.*"),
               expect=("command line", "'--channels'", "'nomatch.*'", "matches no channel", str(f),
                       "bridge.span1.mid.disp_z"))


def _plot_one_pattern_of_two(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta())
    return Run(argv=(*plot(f), "--channels", "car1.*", "car9.body.*"),
               expect=("command line", "'--channels'", "'car9.body.*'", "car1.body.acc_z"))


# ------------------------------------------------------------------ save of a result mutated in Python
_LOAD = "import dataclasses, numpy as np\nfrom tb_exudyn.results import load_results\n"


def _loaded(f: Path) -> str:
    return _LOAD + f"r = load_results({str(f)!r})\n"


def _save_negative_std(d: Path) -> Run:
    f = _rr(d)
    out = d / "copy"
    code = _loaded(f) + f"dataclasses.replace(r, std=-r.std).save({str(out)!r})\n"
    return Run(code=code, expect=(str(out / "arrays.npz"), "'std'", "negative", "not saved"))


def _save_over_itself(d: Path) -> Run:
    """A bad result saved over the folder it came from: refused, the good folder left as it was."""
    f = _rr(d)
    code = _loaded(f) + f"dataclasses.replace(r, band=(0.5, 1e308)).save({str(f)!r})\n"
    return Run(code=code, expect=(_meta(f), "'band_hz'", "not saved"))


def _save_warnings_mutated(d: Path) -> Run:
    f = _rr(d)
    out = d / "copy"
    code = _loaded(f) + f"r.provenance['warnings'] = 'one warning'\nr.save({str(out)!r})\n"
    return Run(code=code, expect=(str(out / "meta.json"), "'provenance.warnings'", "not saved"))


def _save_nan_mean(d: Path) -> Run:
    f = _rr(d)
    out = d / "copy"
    code = _loaded(f) + f"m = r.mean.copy(); m[0, 0] = np.nan\ndataclasses.replace(r, mean=m).save({str(out)!r})\n"
    return Run(code=code, expect=(str(out / "arrays.npz"), "'mean'", "non-finite", "not saved"))


def _save_int_time(d: Path) -> Run:
    """Integer times would be stored as integers, which load refuses (floating point expected)."""
    f = _rr(d)
    out = d / "copy"
    code = _loaded(f) + f"dataclasses.replace(r, time=np.arange(r.time.size)).save({str(out)!r})\n"
    return Run(code=code, expect=(str(out / "arrays.npz"), "'time'", "floating point", "not saved"))


def _save_th_channel_mutated(d: Path) -> Run:
    f = write_result(d / "det", th_arrays(), th_meta())
    out = d / "copy"
    code = (_loaded(f) + "r.channels['car1.body.acc_z'] = np.zeros(3)\n"
            + f"r.save({str(out)!r})\n")
    return Run(code=code, expect=(str(out / "arrays.npz"), "'car1.body.acc_z'", "not saved"))


def _save_th_one_time(d: Path) -> Run:
    code = ("import numpy as np\nfrom tb_exudyn.results import TimeHistory\n"
            "TimeHistory(time=np.zeros(1), channels={'car1.body.acc_z': np.zeros(1)}, units={'car1.body.acc_z': "
            f"'m/s^2'}}).save({str(d / 'one')!r})\n")
    return Run(code=code, expect=(str(d / "one" / "arrays.npz"), "'time'", "at least 2", "not saved"))


CASES_RESULTS2: list[Case] = [
    Case("std < 0", "results", _negative_std),
    Case("psd < 0 (plot)", "results", _negative_psd),
    Case("df < 0", "results", _negative_df),
    Case("freq < 0", "results", _negative_freq),
    Case("var_by_type < 0", "results", _negative_var_by_type),
    Case("std_ci < 0", "results", _negative_std_ci),
    Case("std_rate < 0", "results", _negative_std_rate),
    Case("band up to 1e308 Hz", "results", _band_1e308),
    Case("band above the scenario's 100 Hz", "results", _band_above_scenario),
    Case("freq outside band_hz", "results", _freq_outside_band),
    Case("mean 1e300", "results", _mean_1e300),
    Case("psd 1e250", "results", _psd_1e250),
    Case("time history values 1e300 (plot)", "results", _th_values_1e300),
    Case("one output time", "results", _one_output_time),
    Case("no channel", "results", _no_channel),
    Case("psd over no frequency (plot)", "results", _psd_without_freq),
    Case("export of std < 0", "results", _export_negative_std),
    Case("provenance.warnings a string", "results", _warnings_text),
    Case("provenance.warnings numbers", "results", _warnings_of_numbers),
    Case("time history provenance.warnings an object", "results", _warnings_th),
    Case("provenance.damped_modes extra field", "results", _damped_modes_extra_field),
    Case("provenance.damped_modes text frequency", "results", _damped_modes_text_frequency),
    Case("provenance.damping_warnings text frequency", "results", _damping_warning_text_frequency),
    Case("provenance.grid_error text entry", "results", _grid_error_text_entry),
    Case("provenance.derived_channels a list", "results", _derived_channels_list),
    Case("provenance.samples_with_loss_of_contact text", "results", _loss_of_contact_text),
    Case("plot --channels 'nomatch.*'", "results", _plot_no_match),
    Case("plot --channels, second pattern matches nothing", "results", _plot_one_pattern_of_two),
    Case("save: std < 0 set in Python", "results", _save_negative_std),
    Case("save: band 1e308 over its own folder", "results", _save_over_itself),
    Case("save: provenance.warnings set to a string", "results", _save_warnings_mutated),
    Case("save: NaN mean set in Python", "results", _save_nan_mean),
    Case("save: integer times", "results", _save_int_time),
    Case("save: time history channel of another length", "results", _save_th_channel_mutated),
    Case("save: time history of one output time", "results", _save_th_one_time),
]
