"""Hostile inputs of the check's stochastic rows (`tb-exudyn check --stochastic`, issue 25 item 4) as data,
in the form of tests/reliability/cases.py: each case builds its files in a scratch folder and must end in
exit status 2 with one line naming the option (or the file and key), no traceback, and nothing written.
Every case is refused before any PEM run. Group: "stochastic"."""

from __future__ import annotations

from pathlib import Path

from .cases import Case, Run

GROUP = "stochastic"
MODELS = Path(__file__).resolve().parents[2] / "models"


def _argv(d: Path, *more: str, trains: tuple[str, ...] = ("ice_mttm",)) -> tuple[str, ...]:
    return ("check", "single_span_32m", "--line-speed-kmh", "250", "--trains", *trains,
            "--out", str(d / "out"), "--no-figures", "--no-progress", *more)


def _cli(*more: str, expect: tuple[str, ...], trains: tuple[str, ...] = ("ice_mttm",)):
    def build(d: Path) -> Run:
        return Run(argv=_argv(d, *more, trains=trains), expect=expect)
    return build


def _speeds_without_stochastic(d: Path) -> Run:
    return Run(argv=_argv(d, "--stochastic-speeds", "250"), expect=("--stochastic-speeds", "with --stochastic only"))


def _scenario_without_stochastic(d: Path) -> Run:
    return Run(argv=_argv(d, "--stochastic-scenario", "quick"), expect=("--stochastic-scenario", "--stochastic"))


def _scenario_file(d: Path, old: str, new: str) -> Path:
    text = (MODELS / "scenarios" / "quick.toml").read_text()
    assert old in text, old
    p = d / "sc.toml"
    p.write_text(text.replace(old, new))
    return p


def _scenario_file_bad_key(d: Path) -> Run:
    p = _scenario_file(d, "n_freq = 120", "n_freq = 120\nn_frequencies = 3")
    return Run(argv=_argv(d, "--stochastic", "--stochastic-scenario", str(p)), expect=(str(p), "n_frequencies"))


def _scenario_band_empty_at_the_speeds(d: Path) -> Run:
    # valid as a file (0.6-2 Hz, time step 0.05 s), but at 144-300 km/h the wavelength band 1-5 m lies at
    # 8-83 Hz, above the 2 Hz the time step resolves: every speed's grid is empty
    p = _scenario_file(d, "time_step = 0.001\noutput_step = 0.01", "time_step = 0.05\noutput_step = 0.05")
    p.write_text(p.read_text().replace("freq_max = 30.0", "freq_max = 2.0").replace("wavelength_max = 120.0",
                                                                                     "wavelength_max = 5.0"))
    return Run(argv=_argv(d, "--stochastic", "--stochastic-scenario", str(p), "--stochastic-speeds", "250"),
               expect=("--stochastic-scenario", str(p), "250 km/h", "analysis.freq_min", "empty frequency band"))


def _python(code: str, expect: tuple[str, ...]):
    def build(d: Path) -> Run:
        return Run(code="from tb_exudyn.codes import check\n" + code.format(out=str(d)), expect=expect)
    return build


CASES_STOCHASTIC: list[Case] = [
    Case("stochastic: --stochastic-speeds without --stochastic", GROUP, _speeds_without_stochastic),
    Case("stochastic: --stochastic-scenario without --stochastic", GROUP, _scenario_without_stochastic),
    Case("stochastic: only HSLM-A trains (moving forces)", GROUP,
         _cli("--stochastic", trains=("hslm_a",), expect=("--stochastic", "vehicle models", "ice_mttm"))),
    Case("stochastic: speeds not numbers", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "250,fast", expect=("--stochastic-speeds", "not a number"))),
    Case("stochastic: speeds empty", GROUP,
         _cli("--stochastic", "--stochastic-speeds", ",", expect=("--stochastic-speeds", "no speed"))),
    Case("stochastic: speed below the series (100 km/h)", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "100", expect=("--stochastic-speeds", "144 to 300 km/h"))),
    Case("stochastic: speed above 1.2 x the line speed", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "250,301", expect=("--stochastic-speeds", "301", "300 km/h"))),
    Case("stochastic: speed nan", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "nan", expect=("--stochastic-speeds", "nan"))),
    Case("stochastic: speed inf", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "inf", expect=("--stochastic-speeds", "inf"))),
    Case("stochastic: a speed twice", GROUP,
         _cli("--stochastic", "--stochastic-speeds", "250,250.0", expect=("--stochastic-speeds", "twice"))),
    Case("stochastic: unknown scenario", GROUP,
         _cli("--stochastic", "--stochastic-scenario", "no_such", expect=("--stochastic-scenario", "no_such", "quick"))),
    Case("stochastic: empty scenario name", GROUP,
         _cli("--stochastic", "--stochastic-scenario", "", expect=("--stochastic-scenario", "unknown scenario"))),
    Case("stochastic: scenario without irregularities", GROUP,
         _cli("--stochastic", "--stochastic-scenario", "fryba_moving_force",
              expect=("--stochastic-scenario", "fryba_moving_force", "track.irregularities"))),
    Case("stochastic: scenario file with an unknown key", GROUP, _scenario_file_bad_key),
    Case("stochastic: scenario whose band is empty at the check's speeds", GROUP, _scenario_band_empty_at_the_speeds),
    Case("stochastic: --workers 0", GROUP,
         _cli("--stochastic", "--workers", "0", expect=("--workers", ">= 1"))),
    Case("stochastic: --workers not a number", GROUP,
         _cli("--stochastic", "--workers", "two", expect=("--workers", "not a whole number"))),
    Case("stochastic: Python stochastic='yes'", GROUP,
         _python("check('single_span_32m', 250, trains=['ice_mttm'], stochastic='yes')",
                 ("check", "stochastic", "True or False"))),
    Case("stochastic: Python speeds as a text", GROUP,
         _python("check('single_span_32m', 250, trains=['ice_mttm'], stochastic=True, stochastic_speeds='250')",
                 ("check", "stochastic_speeds", "numbers"))),
    Case("stochastic: Python without the nominal case", GROUP,
         _python("check('single_span_32m', 250, trains=['ice_mttm'], stochastic=True, cases=['upper'])",
                 ("check", "cases", "nominal"))),
]


def _earlier_page_in_out(d: Path) -> Run:
    (d / "out").mkdir()
    (d / "out" / "check.html").write_text("<html></html>\n")
    return Run(argv=_argv(d, trains=("HSLM-A1",)), expect=(str(d / "out"), "check.html", "--overwrite"))


CASES_STOCHASTIC.append(Case("check: an earlier check.html in --out", GROUP, _earlier_page_in_out))


def _track_under_the_whole_run(d: Path) -> Run:
    # quick with the ballasted track under the whole run (no track.structure_approach): ice_mttm (4 cars) over
    # single_span_32m after 85 m of lead-in, at 250 km/h: 345 m of rails, beyond the dense eigen-solution's 6000 DOFs
    p = _scenario_file(d, "run_out = 10.0", 'run_out = 10.0\nstructure = "ballasted_uic60"')
    return Run(argv=_argv(d, "--stochastic", "--stochastic-scenario", str(p), "--stochastic-speeds", "250"),
               expect=("--stochastic-scenario", str(p), "ice_mttm at 250 km/h", "more than 6000",
                       "track.structure_approach"))


def _creep_cars_on_the_track(d: Path) -> Run:
    # the creep cars' creep rows are not written on the rails: a train of them on a scenario with a track structure
    train = d / "creep.toml"
    train.write_text('name = "creep"\ndescription = "one ICE motor car, creep model"\n[[cars]]\n'
                     'vehicle = "ice_motor_creep"\n')
    p = _scenario_file(d, "run_out = 10.0", 'run_out = 10.0\nstructure = "ballasted_uic60"\nstructure_approach = 3.0')
    return Run(argv=_argv(d, "--stochastic", "--stochastic-scenario", str(p), trains=(str(train),)),
               expect=("--trains", "creep", "creep_car", "car15"))


CASES_STOCHASTIC += [
    Case("stochastic: a track under the whole run, too long", GROUP, _track_under_the_whole_run),
    Case("stochastic: creep cars on a track structure", GROUP, _creep_cars_on_the_track),
]
