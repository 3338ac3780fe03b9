"""Two tracks as data (issue 29): ``bridge.tracks`` read from TOML, the tracks' (offset, height), the
``show`` rows and the run's label, the stations along each track and their labels.

References: the values written in the files and the naming rule of docs/channels.md (stations along a
track: ``span<k>.<st>.track<i>``); exact comparisons (no arithmetic beyond the span fractions, which
are exact binary fractions of whole metres).
"""

from __future__ import annotations

from pathlib import Path

from tb_exudyn.scenario import load_scenario
from tb_exudyn.scenario.sections import track_lines
from tb_exudyn.scenario.show import run_label, scenario_table
from tb_exudyn.system.derived import station_positions, station_track
from tb_exudyn.system.labels import channel_label

TRACKS = """
[[tracks]]
offset = 2.25
height = 1.64

[[tracks]]
offset = -2.25
height = 1.5
"""


def _bridge_text() -> str:
    """single_span_32m given spans 32 + 24 m and two tracks instead of its track_offset / track_height."""
    from tb_exudyn.scenario import model_files

    text = model_files("bridges")["single_span_32m"].read_text()
    text = text.replace("spans = [32.0]", "spans = [32.0, 24.0]\ndeck_width = 12.0").replace("track_offset = 2.5\n", "")
    return text.replace("track_height = 1.64\n", "") + TRACKS


def _scenario(tmp_path: Path, on: int):
    (tmp_path / "b.toml").write_text(_bridge_text())
    p = tmp_path / "sc.toml"
    p.write_text(f'name = "t"\nspeed_kmh = 200.0\nbridge = "b.toml"\n\n[train]\nvehicles = ["ice_motor"]\n\n'
                 f'[track]\non = {on}\n')
    return load_scenario(p)


def test_tracks_read_from_the_file(tmp_path):
    sc = _scenario(tmp_path, 2)
    assert track_lines(sc.bridge) == ((2.25, 1.64), (-2.25, 1.5))
    assert sc.track.on == 2 and sc.bridge.deck_width == 12.0
    # one track: track_offset and track_height, as before
    quick = load_scenario("quick")
    assert track_lines(quick.bridge) == ((2.5, 1.64),) and quick.track.on == 1


def test_show_and_label_name_the_train_track(tmp_path):
    sc = _scenario(tmp_path, 2)
    table = scenario_table(sc)
    assert "(derived) track 1" in table and "(derived) track 2" in table
    lines = table.splitlines()
    i = next(i for i, x in enumerate(lines) if x.startswith("(derived) track 2"))
    line = " ".join([lines[i]] + [x.strip() for x in lines[i + 1:i + 3] if x.startswith(" ")])  # a wrapped meaning
    assert "-2.25, 1.5" in line and "the train's track" in line
    assert "track 2 of 2" in run_label(sc)
    assert "track 1 of" not in run_label(load_scenario("quick")) and "(derived) track" not in scenario_table(load_scenario("quick"))


def test_stations_along_each_track():
    """span<k>.<st>.track<i> lies where span<k>.<st> does; each track gets its own twist stations
    (1.5 m inside each span's ends); on a two-track deck the girder axis carries no deck channels."""
    names = ["span1.mid", "span1.q1.track1", "span2.mid.track2", "pier1.top"]
    at = station_positions(names, (32.0, 24.0))
    assert at["span1.q1.track1"] == 8.0 and at["span2.mid.track2"] == 44.0 and at["span1.mid"] == 16.0
    assert at["span1.start.track1"] == 1.5 and at["span2.end.track2"] == 54.5
    assert "span1.start" not in at and "pier1.top" not in at
    assert station_track("span2.mid.track2", 2) == 2 and station_track("span1.mid", 2) == 0
    assert station_track("span1.mid", 1) == 1 and station_track("span1.start", 1) == 1
    # one track: the plain twist stations, as before
    assert "span1.start" in station_positions(["span1.mid"], (32.0,))


def test_labels_of_track_channels():
    assert channel_label("bridge.span2.mid.track2.acc_z") == "span 2, mid-span, track 2, vertical acceleration"
    assert channel_label("bridge.span1.q1.track1.acc_z_en1990").startswith("span 1, first quarter point, track 1, EN 1990")
    assert channel_label("bridge.span2.mid.acc_z") == "span 2, mid-span, vertical acceleration"


def test_deck_limits_see_every_track():
    """The EN 1990 deck quantities of the limit files (scenario.limits.QUANTITIES) match the channels along
    each track, so the checks take the worst over every track's stations."""
    from tb_exudyn.scenario.limits import QUANTITIES

    for q, name in (("deck_acc_z_en1990", "bridge.span2.mid.track2.acc_z_en1990"),
                    ("deck_twist_3m", "bridge.span1.start.track2.twist_3m"),
                    ("deck_acc_z", "bridge.span1.q1.track1.acc_z")):
        assert QUANTITIES[q].matches(name), (q, name)
