"""What a report page draws by default (issue 49): the figures of the bridge's channels, of the leading
car's and of the channels the checks' verdicts name; the other cars' are left out (about 30 % of the
main job's drawing, docs/speed.md section 15), the page says which and how to draw them, and
``all_figures`` draws them."""

from __future__ import annotations

import re
from dataclasses import replace

import pytest
from synthetic_results import pem_response  # tests/plotting is on sys.path for its tests

from tb_exudyn.plotting import data as pdata
from tb_exudyn.report import page_jobs, write_report

BRIDGE, LEAD, BEHIND = "bridge.span1.mid.acc_z", "car1.axle1.force_y", "car2.axle1.force_y"


@pytest.fixture(scope="module")
def two_cars():
    """The synthetic PEM result cut to a bridge channel and a lateral axle force, the force's copy
    renamed as the second car's (the drawing does not depend on the name's car)."""
    pem = pem_response()
    cut = pdata.channel_subset(pem, [BRIDGE, LEAD, LEAD])
    return replace(cut, channels=(BRIDGE, LEAD, BEHIND), psd_channels=None)


def test_page_channel_keeps_the_bridge_the_leading_car_and_the_deciding_channels():
    assert pdata.page_channel(BRIDGE) and pdata.page_channel("car1.body.acc_y")
    assert not pdata.page_channel("car3.body.acc_z")
    assert pdata.page_channel("car3.body.acc_z", deciding=["car3.body.acc_z"])


def test_the_default_page_leaves_out_the_other_cars_figures_and_says_how_to_draw_them(tmp_path, two_cars,
                                                                                      monkeypatch):
    """The page of a result with a bridge channel, car 1's and car 2's: the bounds, PSD map and
    slices of the bridge and of car 1 (6 figures), car 2's left out and named in one line with the
    commands that draw them; with ``all_figures`` all 9, and no such line; a channel a verdict names
    keeps its figures. The verdicts' deciding channels are set here (the synthetic result's checks
    would decide on whichever channel is worst)."""
    folder = tmp_path / "out"
    two_cars.save(folder / "pem")
    found = [(folder / "pem", two_cars)]
    monkeypatch.setattr(pdata, "deciding_channels", lambda r: [])
    jobs, left_out = page_jobs(folder, found)
    assert sorted((j.channel, j.kind) for j in jobs) == sorted(
        (c, k) for c in (BRIDGE, LEAD) for k in ("bounds", "psd_map", "psd_slices"))
    assert left_out == [BEHIND]
    page = write_report(folder, workers=1).read_text(encoding="utf-8")
    assert len(re.findall(r'src="data:image/png;base64,', page)) == 6
    line = re.search(r'<p class="left-out">([^<]*)</p>', page).group(1)
    assert BEHIND in line and "car 2" in line and "tb-exudyn plot FOLDER" in line and "--figures all" in line
    assert not list((folder / "pem" / "figures").glob(f"{BEHIND}.*"))
    page = write_report(folder, workers=1, all_figures=True).read_text(encoding="utf-8")
    assert len(re.findall(r'src="data:image/png;base64,', page)) == 9 and 'class="left-out"' not in page
    assert len(list((folder / "pem" / "figures").glob(f"{BEHIND}.*.png"))) == 3
    monkeypatch.setattr(pdata, "deciding_channels", lambda r: [BEHIND])
    jobs, left_out = page_jobs(folder, found)
    assert len(jobs) == 9 and left_out == []
