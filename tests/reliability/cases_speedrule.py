"""Hostile inputs of issue 26 item 4 ("one rule for a run at a speed") as data, in the form of cases.py.

A sweep's key quantity that matches no channel of the model was dropped without a word; a speed at
which the speed rule (tb_exudyn.scenario.speed_rule: the band scaled by v / v0, at most
0.1 / time_step) leaves no band must be refused naming the option, for ``run --speed-kmh`` as for the
sweep. Every case ends in exit status 2 with one line naming the option, no traceback, and nothing
written (tests/reliability/test_speedrule.py).
"""

from __future__ import annotations

from pathlib import Path

from .cases import Case, Run

GROUP = "speedrule"

#: quick with a 0.05 s time step and a 0.6-2 Hz band: 0.1 / 0.05 = 2 Hz is the highest band frequency
#: the step allows, so the rule's band at 900 km/h (0.6-2 Hz x 3.6 = 2.16-7.2 Hz, capped at 2 Hz) is empty
COARSE_STEP = ("--set", "analysis.freq_max=2", "--set", "analysis.freq_spacing=linear", "--set",
               "analysis.output_step=0.05", "--set", "analysis.time_step=0.05")


def _sweep_channel_matching_nothing(d: Path) -> Run:
    return Run(argv=("sweep", "quick", "--speeds-kmh", "200,300", "--out", str(d / "out"), "--channels",
                     "bridge.*.acc_z_en1990", "bridge.*.acc_z_en1991"),
               expect=("command line", "--channels", "'bridge.*.acc_z_en1991' matches no channel"))


def _sweep_speed_with_an_empty_band(d: Path) -> Run:
    return Run(argv=("sweep", "quick", *COARSE_STEP, "--speeds-kmh", "200,900", "--out", str(d / "out")),
               expect=("command line", "--speeds-kmh", "at 900 km/h freq_min", "empty frequency band"))


def _run_speed_with_an_empty_band(d: Path) -> Run:
    return Run(argv=("run", "quick", *COARSE_STEP, "--speed-kmh", "900", "--out", str(d / "out")),
               expect=("command line", "--speed-kmh", "900", "freq_min", "empty frequency band"))


def _sweep_python_channel_matching_nothing(d: Path) -> Run:
    return Run(code="from tb_exudyn.scenario import load_scenario\nfrom tb_exudyn.methods.sweep import check_sweep\n"
                    "check_sweep(load_scenario('quick'), [250.0], channels=['car*.body.acc_q'])",
               expect=("run_sweep", "channels", "'car*.body.acc_q' matches no channel"))


def _sweep_speed_whose_track_is_too_long(d: Path) -> Run:
    # the track under the whole run (no track.structure_approach): 197 m of rails at 90 km/h (3950 DOFs), but the
    # speed rule keeps the lead-in's time, 150 m -> 500 m at 300 km/h: 547 m, beyond the dense eigen-solution's 6000
    return Run(argv=("sweep", "yang_yau_sprung_mass", "--speeds-kmh", "90,300", "--out", str(d / "out"), "--set",
                     "track.lead_in=150", "--set", "bridge.track_height=1.0", "--set", "track.structure=ballasted_uic60"),
               expect=("--speeds-kmh", "at 300 km/h", "more than 6000", "track.structure_approach"))


def _sweep_creep_cars_on_a_track(d: Path) -> Run:
    # the creep cars' creep rows are not written on the rails: refused before the base's model (its track) is built
    return Run(argv=("sweep", "li_zhu_2011_creep", "--speeds-kmh", "200,220", "--out", str(d / "out"), "--set",
                     "track.structure=ballasted_uic60", "--set", "track.structure_approach=3"),
               expect=("li_zhu_2011_creep", "train.vehicles", "creep_car", "car15"))


CASES_SPEEDRULE: list[Case] = [
    Case("speedrule: sweep --channels pattern matching no channel", GROUP, _sweep_channel_matching_nothing),
    Case("speedrule: sweep speed whose band the time step empties", GROUP, _sweep_speed_with_an_empty_band),
    Case("speedrule: run --speed-kmh whose band the time step empties", GROUP, _run_speed_with_an_empty_band),
    Case("speedrule: check_sweep channels matching no channel", GROUP, _sweep_python_channel_matching_nothing),
    Case("speedrule: sweep speed whose track is too long", GROUP, _sweep_speed_whose_track_is_too_long),
    Case("speedrule: sweep of creep cars on a track", GROUP, _sweep_creep_cars_on_a_track),
]
