"""What figures and the report show, without matplotlib: display units, labels, crossing events per
car, default channels, PSD statistics (synthetic results with known values)."""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.plotting import data
from tb_exudyn.system.channels import catalogue, rail_channels

import synthetic_results

RIGID = (("y", 1), ("z", 2), ("rx", 3), ("ry", 4), ("rz", 5))
WHEELSET = (("y", 1), ("z", 2), ("rx", 3))

#: every channel kind tb_exudyn.system.channels makes, with its expected label
EXPECTED_LABELS = {
    "bridge.span2.mid.disp_z": "span 2, mid-span, vertical displacement",
    "bridge.span1.q1.acc_y": "span 1, first quarter point, lateral acceleration",
    "bridge.span1.q3.vel_rx": "span 1, third quarter point, torsional angular velocity",
    "bridge.pier1.top.disp_y": "pier 1, top, lateral displacement",
    "car1.body.acc_y": "car 1, body, lateral acceleration",
    "car1.body.disp_rx": "car 1, body, roll angle",
    "car1.body.vel_ry": "car 1, body, pitch angular velocity",
    "car1.bogie1.acc_y": "car 1, leading bogie, lateral acceleration",
    "car1.bogie2.acc_rz": "car 1, trailing bogie, yaw angular acceleration",
    "car1.axle3.disp_y": "car 1, axle 3, wheelset lateral displacement",
    "car1.axle1.acc_rx": "car 1, axle 1, wheelset roll angular acceleration",
    "car1.axle1.left.force_z": "car 1, axle 1, left wheel, vertical wheel-rail force",
    "car1.axle1.right.force_z": "car 1, axle 1, right wheel, vertical wheel-rail force",
    "car1.axle2.force_y": "car 1, axle 2, lateral wheel-rail force",
    "car2.body.acc_z": "car 2, body, vertical acceleration",
    "car2.axle1.disp_z": "car 2, axle 1, wheelset vertical displacement",
    "car2.axle1.force_z": "car 2, axle 1, vertical wheel-rail force",
}


def _all_kinds():
    """The catalogue of a model with every kind of channel: bridge stations (quarter points,
    mid-span, pier top), a car15 (body, bogies, wheelsets, wheel forces), a sprung mass (body,
    wheel, wheel load) and a moving force (its load)."""
    bodies = [("car1.body", 0, RIGID), ("car1.bogie1", 1, RIGID), ("car1.bogie2", 2, RIGID)]
    bodies += [(f"car1.axle{j}", 2 + j, WHEELSET) for j in range(1, 5)]
    bodies += [("car2.body", 7, (("z", 0),)), ("car2.axle1", 8, (("z", 0),))]
    contacts = [f"car1.axle{j}.{side}.force_z" for j in range(1, 5) for side in ("left", "right")]
    contacts += [f"car1.axle{j}.force_y" for j in range(1, 5)] + ["car2.axle1.force_z"]
    rails = rail_channels(contacts, [0] * 8 + [1] * 4 + [0])  # with a track structure: the rail under each wheel
    return catalogue(["span1.q1", "span1.mid", "span1.q3", "span2.q1", "span2.mid", "span2.q3", "pier1.top"],
                     bodies, contacts, ["car3.axle1.force_z"]) + rails


def test_every_channel_kind_has_a_readable_label():
    channels = _all_kinds()
    names = [c.name for c in channels]
    labels = [data.channel_label(n) for n in names]
    unreadable = [n for n, lab in zip(names, labels) if lab == n or "_" in lab]
    assert not unreadable, unreadable
    assert len(set(labels)) == len(labels)  # one label per channel: no two channels read the same
    for name, label in EXPECTED_LABELS.items():
        assert name in names, name  # the expected names are real channel names
        assert data.channel_label(name) == label
    assert data.channel_label("car3.axle1.force_z") == "car 3, axle 1, vertical wheel-rail force"  # a moving force
    assert data.channel_label("car1.axle2.right.rail.acc_z") == "car 1, axle 2, right wheel, rail under it, vertical acceleration"
    assert data.channel_label("car1.axle2.rail.disp_y") == "car 1, axle 2, rails' centre line under the wheelset, lateral displacement"
    assert data.channel_label("car2.axle1.rail.vel_z") == "car 2, axle 1, rail under the wheel, vertical velocity"
    assert data.channel_label("car1.qp.axle1.left") == "car1.qp.axle1.left"  # a derived quantity: its name
    assert data.axis_label("car1.axle2.force_y", "N") == "lateral wheel-rail force [kN]"


def test_display_units_of_every_channel_unit():
    # every unit the catalogue makes has a display unit; factors are the SI prefixes (exact)
    assert {c.unit for c in _all_kinds()} <= set(data.DISPLAY_UNITS)
    assert data.display_unit("N") == data.DisplayUnit("kN", 1e-3)
    assert data.display_unit("m") == data.DisplayUnit("mm", 1e3)
    assert data.display_unit("m/s^2") == data.DisplayUnit("m/s^2", 1.0)
    assert data.display_unit("rad") == data.DisplayUnit("mrad", 1e3)
    assert data.display_unit("") == data.DisplayUnit("", 1.0)  # a ratio stays as it is
    assert data.psd_unit("kN") == "kN^2/Hz" and data.psd_unit("m/s^2") == "(m/s^2)^2/Hz"


@pytest.mark.parametrize("x, text", [(78480.0, "78480"), (0.48812, "0.4881"), (3.5, "3.5"), (9.99996, "10"),
                                     (-0.25, "-0.25"), (1.2e-5, "1.200e-05"), (2.5e7, "2.500e+07"), (0.0, "0"),
                                     (float("nan"), "")])
def test_format_number_has_no_exponent_in_the_engineering_range(x, text):
    assert data.format_number(x) == text


def test_crossing_events_per_car():
    """Two ICE motor cars (axles 0, 2.5, 17.375, 19.875 m behind each car's first; car 2 starts
    one car length, 26.4 m, behind car 1) at 250 km/h, 30 m before a 32 m span."""
    sc = synthetic_results.scenario()
    car = sc.train.vehicles[0]
    sc = sc.replace(train=sc.train.replace(vehicles=(car, car)))
    v = 250 / 3.6
    a = car.axle_offsets
    L = car.length
    c2 = data.crossing_times(sc, 2)
    assert (c2.first_on, c2.first_off) == pytest.approx(((30 + L + a[0]) / v, (62 + L + a[0]) / v), rel=1e-12)
    assert (c2.last_on, c2.last_off) == pytest.approx(((30 + L + a[-1]) / v, (62 + L + a[-1]) / v), rel=1e-12)
    assert c2.position(c2.first_on) == pytest.approx(0.0, abs=1e-9) and c2.who == "car 2"
    train = data.crossing_times(sc)
    assert train.first_on == data.crossing_times(sc, 1).first_on and train.last_off == c2.last_off
    assert data.channel_crossing(sc, "car2.axle1.force_y") == c2
    assert data.channel_crossing(sc, "bridge.span1.mid.acc_z") == train
    assert c2.marks()[0][1] == "car 2: first axle enters" and train.marks()[0][1] == "first axle enters"
    with pytest.raises(ValueError, match="cars 1-2"):
        data.crossing_times(sc, 3)


def test_default_channels_of_the_reference_study_layout():
    stations = [f"span{s}.{p}" for s in (1, 2, 3) for p in ("q1", "mid", "q3")] + ["pier1.top", "pier2.top"]
    bodies = []
    contacts = []
    for k in (1, 2, 3, 4):
        bodies += [(f"car{k}.body", 0, RIGID), (f"car{k}.bogie1", 0, RIGID), (f"car{k}.bogie2", 0, RIGID)]
        bodies += [(f"car{k}.axle{j}", 0, WHEELSET) for j in range(1, 5)]
        contacts += [f"car{k}.axle{j}.{s}.force_z" for j in range(1, 5) for s in ("left", "right")]
        contacts += [f"car{k}.axle{j}.force_y" for j in range(1, 5)]
    names = [c.name for c in catalogue(stations, bodies, contacts, [])]
    assert len(names) == 471  # the li_zhu_2011 result's channel count

    th = synthetic_results.time_history()  # a stand-in result with these names: only the names matter
    fake = type(th)(time=th.time, channels={n: th.time for n in names}, units={n: "m" for n in names})
    chosen = data.default_channels(fake)
    study = ["bridge.span2.mid.disp_y", "bridge.span2.mid.acc_y", "car1.body.disp_y", "car1.body.acc_y",
             "car1.bogie1.disp_y", "car1.bogie1.acc_y", "car1.axle1.force_y", "car1.axle1.left.force_z",
             "car1.axle1.right.force_z"]
    checked = [f"bridge.span{s}.mid.acc_z" for s in (1, 2, 3)] + [f"car{k}.body.acc_{c}" for k in (1, 2, 3, 4)
                                                                  for c in "yz"] + [f"car{k}.axle1.force_y" for k in (2, 3, 4)]
    assert set(chosen) == set(study) | set(checked) | {"bridge.span2.mid.disp_z"}
    assert chosen == [n for n in names if n in chosen]  # stored order


def test_channel_subset_keeps_the_rows(pem, mc):
    sub = data.channel_subset(pem, ["car1.axle1.force_y", "bridge.span1.mid.acc_z"])
    assert sub.channels == ("car1.axle1.force_y", "bridge.span1.mid.acc_z") and sub.units == ("N", "m/s^2")
    assert np.array_equal(sub.psd[0], pem.psd[2]) and np.array_equal(sub.std[1], pem.std[0])
    m = data.channel_subset(mc, ["car1.body.acc_y"])
    assert np.array_equal(m.samples[:, 0], mc.samples[:, 1]) and np.array_equal(m.std_ci[:, 0], mc.std_ci[:, 1])


def _one_channel_psd(pem, S):
    """The synthetic PEM result with channel 0's PSD map replaced by S (nf, nt) and sigma from it."""
    psd = pem.psd.copy()
    psd[0] = S
    std = pem.std.copy()
    std[0] = np.sqrt(S.T @ pem.df)
    return type(pem)(**{**pem.__dict__, "psd": psd, "std": std})


def test_psd_peak_band_and_low_frequency_content(pem):
    """A map with one known peak cell inside the channel's crossing (first axle on to last axle
    off) and a larger one before it, in the start-up on the approach, which the readings ignore;
    and a map whose variance sits in the lowest cell."""
    nf, nt = pem.freq.size, pem.time.size
    ch = pem.channels[0]
    c = data.channel_crossing(pem.scenario, ch)
    inside = int(np.flatnonzero(pem.time >= (c.first_on + c.last_off) / 2)[0])
    before = int(np.flatnonzero(pem.time < c.first_on)[-1])
    S = np.full((nf, nt), 1e-6)
    S[3, inside] = 1.0  # peak: f = 7 Hz in the crossing, and all but 5e-6 of the variance at that time
    S[5, before] = 10.0  # larger, at 11 Hz, before the car reaches the bridge
    r = _one_channel_psd(pem, S)
    assert data.psd_peak(r, ch) == (pytest.approx(7.0), pytest.approx(pem.time[inside]))
    assert data.psd_band(r, ch, 0.99) == (pytest.approx(7.0), pytest.approx(7.0))
    assert data.psd_band(r, ch, 0.999999999) == (pytest.approx(1.0), pytest.approx(11.0))
    assert data.crossing_columns(r, ch).sum() == np.sum((pem.time >= c.first_on) & (pem.time <= c.last_off))
    assert not data.low_frequency_content(r, ch)  # median 7 Hz > 12 Hz / 10
    low = np.full((nf, nt), 1e-6)
    low[0] = 1.0  # the variance at 1 Hz, below a tenth of the 12 Hz band edge
    assert data.low_frequency_content(_one_channel_psd(pem, low), ch)


def test_band_statistics_of_a_known_band(pem):
    """mean = 1 and sigma = 0.5 (band 1 +- 1.5 crosses zero) during the crossing's first half, sigma 0.1 after."""
    c = data.crossing_times(pem.scenario)
    t = pem.time
    mean = np.ones((len(pem.channels), t.size))
    std = np.where(t < (c.first_on + c.last_off) / 2, 0.5, 0.1) * np.ones_like(mean)
    r = type(pem)(**{**pem.__dict__, "mean": mean, "std": std})
    on = (t >= c.first_on) & (t <= c.last_off)
    expected = np.mean(t[on] < (c.first_on + c.last_off) / 2)
    assert data.band_across_zero_share(r, r.channels[0]) == pytest.approx(expected, abs=1e-12)
    assert data.sigma_to_mean_ratio(r, r.channels[0]) == pytest.approx(1.5)
