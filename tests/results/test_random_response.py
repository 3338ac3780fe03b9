"""RandomResponse: bounds, summary, and the npz + JSON round trip (no pickle)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.results.random_response import RandomResponse, load_random_response


def _response(with_psd=True):
    rng = np.random.default_rng(3)
    nc, nf, nt = 3, 5, 7
    psd = rng.random((nc, nf, nt)) if with_psd else None
    df = np.full(nf, 0.5)
    std = np.sqrt(np.einsum("cft,f->ct", psd, df)) if with_psd else rng.random((nc, nt))
    return RandomResponse(
        method="pem", time=np.arange(nt) * 0.01, channels=("a.disp_z", "a.acc_z", "b.force_z"),
        units=("m", "m/s^2", "N"), mean=rng.standard_normal((nc, nt)), std=std, band=(0.25, 2.75),
        scenario=tbx.load_scenario("quick"), freq=0.5 + 0.5 * np.arange(nf), df=df, psd=psd,
        types=("german_low.vertical",), provenance={"engine": "test", "seconds": 1.5},
    )


def test_bounds_are_mean_plus_minus_k_sigma():
    r = _response()
    lo, hi = r.bounds(3)
    assert np.array_equal(lo, r.mean - 3 * r.std) and np.array_equal(hi, r.mean + 3 * r.std)
    rows = r.summary_rows(3)
    assert rows[1][0] == "a.acc_z" and rows[1][1] == "m/s^2"
    assert rows[1][4] == pytest.approx(np.max(np.abs(r.mean[1]) + 3 * r.std[1]), rel=1e-15)


def test_save_load_round_trip_is_exact(tmp_path):
    r = _response()
    r.save(tmp_path / "pem")
    back = load_random_response(tmp_path / "pem")
    for name in ("time", "mean", "std", "freq", "df", "psd"):
        assert np.array_equal(getattr(back, name), getattr(r, name)), name
    assert back.channels == r.channels and back.units == r.units and back.band == r.band
    assert back.scenario == r.scenario and back.provenance == r.provenance
    assert back.var_by_type is None
    meta = json.loads((tmp_path / "pem" / "meta.json").read_text())
    assert meta["format"].startswith("tb_exudyn.random_response")


def test_select_and_unknown_channel():
    r = _response(with_psd=False)
    assert r.select("a.*") == ["a.disp_z", "a.acc_z"]
    with pytest.raises(KeyError, match="no channel"):
        r.index("c.nothing")


def test_channels_by_name_and_plot_hands_off_to_plotting():
    """A random response gives one channel's statistics by name (the same arrays as the rows) and
    ``plot`` returns the plotting function's figure; a time history the same for its values; an
    unknown channel or figure kind is refused by name."""
    from matplotlib.figure import Figure

    from tb_exudyn.errors import SettingError
    from tb_exudyn.results import TimeHistory

    r = _response()
    name = r.channels[1]
    ch = r[name]
    assert ch.unit == r.units[1] and np.array_equal(ch.std, r.std[1]) and np.array_equal(ch.psd, r.psd[1])
    lo, hi = ch.bounds(2.0)
    assert np.array_equal(hi, r.mean[1] + 2.0 * r.std[1])
    assert isinstance(r.plot(name), Figure) and isinstance(r.plot(name, "psd_map"), Figure)
    with pytest.raises(KeyError, match="no channel 'nope'"):
        r["nope"]
    with pytest.raises(SettingError, match="key 'kind'"):
        r.plot(name, "spectrogram")
    th = TimeHistory(time=r.time, channels={name: r.mean[1]}, units={name: r.units[1]})
    assert np.array_equal(th[name], r.mean[1]) and isinstance(th.plot(name), Figure)
