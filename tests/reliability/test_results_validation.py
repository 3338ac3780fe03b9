"""Issue 27: results are validated on load and before save, loaded arrays are read-only, and plots
and reports of odd but loadable results do not fail.

The impossible results (tests/reliability/cases_results2.py) end like every hostile input: exit
status 2, one line naming the file (or the option) and the key, no traceback, nothing written.
The other tests here check what must still work: the library's own kinds of result save and load
unchanged, a loaded result's arrays refuse writes, the band limit is the scenario's, and odd
results that load (zero sigma, PSDs of 1e-300, values of 1e100, NaN rates) draw and report.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn.cli import main
from tb_exudyn.errors import ResultsError
from tb_exudyn.results import load_results
from tb_exudyn.results.random_response import band_limit, load_random_response
from tb_exudyn.results.time_history import load_time_history

from .cases_results2 import CASES_RESULTS2
from .test_cases import assert_one_clear_error

# the plotting tests' small synthetic results on the 'quick' scenario (tests/plotting is not a package)
_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)
pem_response, mc_response, time_history = synthetic.pem_response, synthetic.mc_response, synthetic.time_history


@pytest.mark.parametrize("case", CASES_RESULTS2, ids=[c.id for c in CASES_RESULTS2])
def test_impossible_result_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_cases_are_in_group_results():
    assert {c.group for c in CASES_RESULTS2} == {"results"}
    assert len({c.id for c in CASES_RESULTS2}) == len(CASES_RESULTS2)


@pytest.mark.parametrize("make", [pem_response, mc_response, time_history])
def test_valid_results_save_and_load_unchanged(make, tmp_path):
    """The kinds of result the library writes (PEM with a PSD map, Monte Carlo with samples and
    intervals, a time history) pass the checks: saved, loaded, the same numbers bit for bit."""
    result = make()
    result.save(tmp_path / "r")
    back = load_results(tmp_path / "r")
    if hasattr(result, "std"):
        for name in ("time", "mean", "std", "freq", "df", "psd", "samples", "std_ci", "mean_ci"):
            a, b = getattr(result, name), getattr(back, name)
            assert (a is None and b is None) or np.array_equal(a, b), name
        assert back.band == result.band
    else:
        assert all(np.array_equal(result[c], back[c]) for c in result.channels)


def test_loaded_arrays_are_read_only(tmp_path):
    """A loaded result is what its files hold: writing into its arrays raises (numpy's ValueError),
    so a result cannot drift from its folder unnoticed; a copy is writable."""
    pem_response().save(tmp_path / "pem")
    time_history().save(tmp_path / "det")
    pem, th = load_random_response(tmp_path / "pem"), load_time_history(tmp_path / "det")
    for a in (pem.time, pem.mean, pem.std, pem.freq, pem.df, pem.psd, th.time, *th.channels.values()):
        assert not a.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        pem.std[0, 0] = -1.0
    with pytest.raises(ValueError, match="read-only"):
        th["car1.body.acc_y"][0] = np.nan
    copy = pem.std.copy()
    copy[0, 0] = 1.0


def test_band_limit_is_the_scenarios():
    """The quick scenario of the synthetic results: time_step 1e-3 s gives 0.1 / 1e-3 = 100 Hz;
    250 km/h over wavelength_min 1 m gives 69.44 Hz; the limit is the larger (plus 1e-9 relative)."""
    sc = pem_response().scenario
    assert sc.analysis.time_step == 1e-3 and sc.track.wavelength_min == 1.0 and sc.speed_kmh == 250.0
    limit, text = band_limit(sc)
    assert limit == pytest.approx(100.0, rel=2e-9) and limit >= 100.0
    assert "100 Hz" in text and "69.44 Hz" in text
    fast_short = sc.replace(speed_kmh=400.0, track=sc.track.replace(wavelength_min=0.5))
    assert band_limit(fast_short)[0] == pytest.approx(400 / 3.6 / 0.5, rel=2e-9)  # 222.2 Hz: Monte Carlo's band


def test_band_at_the_limit_loads(tmp_path):
    """A band whose upper edge is the limit itself (100 Hz, PEM's highest allowed freq_max here) loads."""
    pem = pem_response()
    dataclasses.replace(pem, band=(0.0, 100.0)).save(tmp_path / "pem")
    assert load_random_response(tmp_path / "pem").band == (0.0, 100.0)
    with pytest.raises(ResultsError, match="band_hz"):
        dataclasses.replace(pem, band=(0.0, 100.001)).save(tmp_path / "pem2")
    assert not (tmp_path / "pem2").exists()


def test_a_refused_save_leaves_the_old_result(tmp_path):
    pem = pem_response()
    pem.save(tmp_path / "pem")
    before = (tmp_path / "pem" / "arrays.npz").read_bytes(), (tmp_path / "pem" / "meta.json").read_bytes()
    with pytest.raises(ResultsError, match=r"'std'.*not saved"):
        dataclasses.replace(pem, std=-pem.std).save(tmp_path / "pem")
    assert ((tmp_path / "pem" / "arrays.npz").read_bytes(), (tmp_path / "pem" / "meta.json").read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pem"]


def _odd_results() -> dict[str, object]:
    pem, mc = pem_response(), mc_response()
    nt = pem.time.size
    r = dataclasses.replace
    return {
        "zero sigma": r(pem, std=0 * pem.std, psd=0 * pem.psd),
        "psd 1e-300": r(pem, std=1e-150 + 0 * pem.std, psd=1e-300 + 0 * pem.psd),
        "values 1e100": r(pem, mean=1e100 + 0 * pem.mean, std=1e100 + 0 * pem.std, psd=1e200 + 0 * pem.psd),
        "two output times": r(pem, time=pem.time[:2], mean=pem.mean[:, :2], std=pem.std[:, :2], psd=pem.psd[:, :, :2]),
        "NaN rates": r(pem, mean_rate=np.full((4, nt), np.nan), std_rate=np.zeros((4, nt)), rho=np.full((4, nt), np.nan),
                       bandwidth=np.full((4, nt), np.nan)),
        "Monte Carlo inf samples": r(mc, samples=np.full_like(mc.samples, np.inf), sample_min=np.full((5, 4), -np.inf),
                                     sample_max=np.full((5, 4), np.nan), min_wheel_force=np.full(5, np.nan)),
        "odd provenance": r(pem, provenance={"warnings": ["<script>alert(1)</script>", "x" * 5000], "damped_modes": [],
                                             "grid_error": "not estimated", "seconds": math.nan, "deep": {"a": [[[]]]}}),
        "unknown units and names": r(pem, units=("", "kg", "m^2/s^3", "rad"),
                                     channels=("a", "b.c", "x_1.y_2.z", "car99.axle7.left.force_z")),
        "time history of 1e100": dataclasses.replace(time_history(), channels={
            c: 1e100 + 0 * v for c, v in time_history().channels.items()}),
    }


@pytest.mark.parametrize("name", list(_odd_results()))
def test_odd_but_loadable_results_plot_and_report(name, tmp_path, capsys):
    """Results the checks let through, however odd, are drawn and reported: exit 0, no error
    (before: PSD maps of 1e-300 failed in matplotlib's colour bar)."""
    result = _odd_results()[name]
    folder = tmp_path / "r"
    result.save(folder / ("det" if not hasattr(result, "method") else "pem" if result.method == "pem" else "mc"))
    assert main(["plot", str(folder)]) == 0
    assert main(["report", str(folder)]) == 0
    err = capsys.readouterr().err
    assert "Traceback" not in err and "error" not in err, err
    page = (folder / "report.html").read_text()
    if name == "odd provenance":
        assert "<script>alert(1)</script>" not in page and "&lt;script&gt;alert(1)&lt;/script&gt;" in page


def test_provenance_as_the_code_writes_it_passes_the_checks(tmp_path):
    """The provenance fields the report and the checks read, made by the functions that write them
    in a run (the damping guard's warnings, the modal table's rows as the report reads them, the grid
    error, the derived channels, the Monte Carlo contact summary), pass the checks after a JSON round
    trip, and a result carrying them saves and loads; each broken as a user could break it is refused."""
    from tb_exudyn.methods.grid_error import grid_error_from_sigma
    from tb_exudyn.methods.monte_carlo import contact_provenance
    from tb_exudyn.report.entries import ModeEntry
    from tb_exudyn.results.metadata import PROVENANCE_FIELDS
    from tb_exudyn.system.damping_guard import DampingWarning
    from tb_exudyn.system.derived import DerivedCatalogue, DerivedChannel, derived_provenance

    t = np.linspace(0.0, 1.0, 11)
    sigma = np.ones((1, 11))
    sperling = DerivedChannel("car1.body.sperling_z", "", "sperling", (("car1.body.acc_z", 1.0),),
                              weighting="vertical", window=5.0, description="Sperling")
    catalogue = DerivedCatalogue(channels=(sperling,), auxiliary=(), shapes=np.zeros((0, 3, 0)))
    provenance = {
        "warnings": ["a warning"],
        "damping_warnings": [dataclasses.asdict(DampingWarning(7, "bogie yaw", "vehicle", 8.3, 1e-4, math.inf, 0.27,
                                                               ("car1.*",), "lightly damped"))],
        "damped_modes": [dataclasses.asdict(ModeEntry(0.86, 0.35, "car 1, body bounce", "at rest", ""))],
        "grid_error": grid_error_from_sigma(t, ["car1.body.acc_z"], sigma, 1.01 * sigma).as_dict(),
        "derived_channels": derived_provenance(catalogue, [sperling]),
        **contact_provenance(np.array([np.nan, np.nan]), np.zeros(0, dtype=int)),  # min_wheel_force_N None
        "seconds": 3.1,
    }
    assert set(provenance) == set(PROVENANCE_FIELDS)
    provenance = json.loads(json.dumps(provenance))
    for key, (ok, _) in PROVENANCE_FIELDS.items():
        assert ok(provenance[key]), key
    pem = pem_response()
    dataclasses.replace(pem, provenance=provenance).save(tmp_path / "pem")
    assert load_random_response(tmp_path / "pem").provenance == provenance
    broken = {"warnings": [{"text": "a warning"}], "damping_warnings": [{"frequency": None}],
              "damped_modes": [{**provenance["damped_modes"][0], "note": "x"}],
              "grid_error": {"channels": {"car1.body.acc_z": {"rel_deviation": None}}},
              "derived_channels": {"channels": {"car1.body.sperling_z": {"window": "5 s"}}},
              "samples_with_loss_of_contact": -1, "min_wheel_force_N": "low", "seconds": "3"}
    broken_too = [("samples_with_loss_of_contact", math.inf), ("warnings", "one warning"), ("damped_modes", {})]
    for key, value in broken.items():
        with pytest.raises(ResultsError, match=rf"'provenance\.{key}'.*not saved"):
            dataclasses.replace(pem, provenance={**provenance, key: value}).save(tmp_path / "bad")
        assert not (tmp_path / "bad").exists()
    for key, value in broken_too:  # int(inf) in the checks' loss-of-contact caveat would raise
        with pytest.raises(ResultsError, match=rf"'provenance\.{key}'"):
            dataclasses.replace(pem, provenance={**provenance, key: value}).save(tmp_path / "bad")


def test_report_warnings_of_a_result_built_in_python():
    """A result made in Python (not loaded, so not checked) whose provenance ``warnings`` is one string
    or a number: the warnings section shows it as one warning instead of raising a TypeError."""
    from tb_exudyn.report.sections import warnings_section

    pem = pem_response()
    for value, shown, count in (("grid too coarse", "grid too coarse", 1), (5, "5", 1), (["a", "b"], "b", 2),
                                (None, "None recorded", 0)):
        html = warnings_section([(Path("pem"), dataclasses.replace(pem, provenance={"warnings": value}))])
        assert shown in html and html.count('class="warn"') == count  # a string is one warning, not letters


def test_float32_psd_map_loads_without_warning(tmp_path):
    """A PEM run keeps its PSD maps in float32 (the quick run's arrays.npz); the magnitude check must
    not compare them against 1e200 in float32 (numpy's 'overflow encountered in cast' warning, which
    `tb-exudyn export` printed)."""
    import warnings

    pem = pem_response()
    dataclasses.replace(pem, psd=pem.psd.astype(np.float32)).save(tmp_path / "pem")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = load_random_response(tmp_path / "pem")
    assert back.psd.dtype == np.float32 and np.array_equal(back.psd, pem.psd.astype(np.float32))
