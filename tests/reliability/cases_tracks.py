"""Hostile two-track data (issue 29: ``bridge.tracks``, ``track.on``) as data, in the form of cases.py.

A track off the deck (its centre line, or one of its rails, beyond half the deck's width), tracks that
overlap, a track index the bridge does not have (too high, 0, on a one-track bridge), a bridge giving
both ``track_offset`` and ``tracks``; in files (``tb-exudyn show`` / ``modes``) and built in Python.
Every case ends in exit status 2 with one line naming the file (or the class) and the key, no
traceback, and nothing written (tests/reliability/test_tracks.py).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from .cases import Case, Run
from .cases_cont import SECTION

GROUP = "tracks"

GIRDER = "[girder]\n" + SECTION.format(E="3.45e10")


def _bridge(d: Path, offsets: tuple[float, ...] = (2.5, -2.5), deck_width: float = 12.0, extra: str = "") -> Path:
    """A one-span simple_beam bridge file with one [[tracks]] table per offset (height 1.64 m)."""
    text = f'kind = "simple_beam"\nname = "two_tracks"\nsource = "test"\nspans = [32.0]\ndeck_width = {deck_width}\n'
    text += extra + "\n" + GIRDER + "\n"
    for e in offsets:
        text += f"[[tracks]]\noffset = {e}\nheight = 1.64\n\n"
    p = d / "two_tracks.toml"
    p.write_text(text)
    return p


def _scenario(d: Path, bridge: str, on: int = 1) -> Path:
    p = d / "sc.toml"
    p.write_text(f'name = "tracks"\nspeed_kmh = 250.0\nbridge = "{bridge}"\n\n[train]\nvehicles = ["ice_motor"]\n\n'
                 f'[track]\non = {on}\nirregularities = ["german_low.vertical"]\nlead_in = 85.0\nrun_out = 10.0\n\n'
                 '[analysis]\nmode_max_frequency = 40.0\n')
    return p


def _show_case(expect: tuple[str, ...], on: int = 1, command: str = "show", **bridge) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        b = _bridge(d, **bridge)
        sc = _scenario(d, b.name, on)
        return Run(argv=(command, str(sc)), expect=expect)
    return build


def _bridge_file_case(expect: tuple[str, ...], **bridge) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        b = _bridge(d, **bridge)
        return Run(argv=("modes", str(_scenario(d, b.name))), expect=(str(b.resolve()),) + expect)
    return build


def _on_one_track_bridge(d: Path) -> Run:
    sc = _scenario(d, "single_span_32m", on=2)
    return Run(argv=("show", str(sc)), expect=(str(sc), "'track.on'", "1 ... 1", "no such track"))


def _set_track_on(d: Path) -> Run:
    b = _bridge(d)
    sc = _scenario(d, b.name)
    return Run(argv=("show", str(sc), "--set", "track.on=5"), expect=("'--set'", "track.on: 1 ... 2", "no such track"))


def _python_off_deck(d: Path) -> Run:
    code = ("from tb_exudyn.scenario import load_bridge\nfrom tb_exudyn.scenario.model import SimpleBeam, TrackLine\n"
            "g = load_bridge('single_span_32m').girder\n"
            "SimpleBeam(name='b', spans=(32.0,), girder=g, deck_width=10.0, "
            "tracks=(TrackLine(offset=2.5), TrackLine(offset=-7.0)))\n")
    return Run(code=code, expect=("'tracks[1].offset'", "off the deck", "deck_width / 2 = 5 m"))


def _python_replace_on(d: Path) -> Run:
    code = ("from tb_exudyn.scenario import load_scenario\n"
            "sc = load_scenario('quick')\n"
            "sc.replace(track=sc.track.replace(on=2))\n")
    return Run(code=code, expect=("Scenario.replace", "'track.on'", "no such track"))


def _modal_table(d: Path, extra: str, tracks: tuple[str, ...]) -> Path:
    """A modal_table bridge (the good tables of cases_modal) with one [[tracks]] table per shapes file name
    (only shapes.csv exists)."""
    from .cases_modal import _bridge as modal_bridge

    b = modal_bridge(d)
    text = b.read_text().replace('shapes = "shapes.csv"\n', extra)
    for i, name in enumerate(tracks):
        text += f'\n[[tracks]]\nshapes = "{name}"\noffset = {2.5 - 5.0 * i}\n'
    b.write_text(text)
    return b


def _modal_both(d: Path) -> Run:
    b = _modal_table(d, 'shapes = "shapes.csv"\n', ("shapes.csv", "shapes.csv"))
    return Run(argv=("modes", str(_scenario(d, b.name))), expect=(str(b.resolve()), "'tracks'", "not both"))


def _modal_missing_track_file(d: Path) -> Run:
    b = _modal_table(d, "", ("shapes.csv", "track2.csv"))
    return Run(argv=("modes", str(_scenario(d, b.name, on=2))), expect=("track2.csv",))


def _modal_on_three(d: Path) -> Run:
    b = _modal_table(d, "", ("shapes.csv", "shapes.csv"))
    sc = _scenario(d, b.name, on=3)
    return Run(argv=("show", str(sc)), expect=(str(sc), "'track.on'", "1 ... 2"))


CASES_TRACKS: list[Case] = [
    Case("track centre line off the deck", GROUP,
         _bridge_file_case(("'tracks[1].offset'", "off the deck", "deck_width / 2 = 6 m"), offsets=(2.5, -6.5))),
    Case("track's rail off the deck", GROUP,
         _show_case(("'bridge.tracks[0].offset'", "a rail off the deck", "deck_width / 2 = 4.5 m"),
                    offsets=(4.0, -2.0), deck_width=9.0)),
    Case("tracks overlap", GROUP,
         _show_case(("'bridge.tracks[1].offset'", "tracks overlap", "from track 1"), offsets=(1.0, 0.2))),
    Case("track.on = 3 on a two-track bridge", GROUP,
         _show_case(("'track.on'", "1 ... 2", "no such track"), on=3)),
    Case("track.on = 3, modes", GROUP,
         _show_case(("'track.on'", "1 ... 2", "no such track"), on=3, command="modes")),
    Case("track.on = 0", GROUP, _show_case(("'track.on'",), on=0)),
    Case("track.on = 2 on a one-track bridge", GROUP, _on_one_track_bridge),
    Case("--set track.on=5", GROUP, _set_track_on),
    Case("track_offset and tracks", GROUP,
         _bridge_file_case(("'tracks'", "not both"), extra="track_offset = 2.5")),
    Case("modal_table with shapes and tracks", GROUP, _modal_both),
    Case("modal_table, a track's shapes file missing", GROUP, _modal_missing_track_file),
    Case("modal_table, track.on = 3 of 2", GROUP, _modal_on_three),
    Case("SimpleBeam() with a track off the deck", GROUP, _python_off_deck),
    Case("Scenario.replace to track 2 of a one-track bridge", GROUP, _python_replace_on),
]
