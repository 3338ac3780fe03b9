"""Small synthetic results on the library's 'quick' scenario (no solver run), shared by the plotting,
report and export tests."""

from __future__ import annotations

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.results import RandomResponse, TimeHistory

CHANNELS = ("bridge.span1.mid.acc_z", "car1.body.acc_y", "car1.axle1.force_y", "car1.axle1.left.force_z")
UNITS = ("m/s^2", "m/s^2", "N", "N")


def scenario():
    """The library's 'quick' scenario with the numbers the tests rely on pinned: one ICE motor car
    over one 32 m span at 250 km/h, 30 m of track before the bridge and 10 m after."""
    sc = tbx.load_scenario("quick")
    sc = sc.replace(speed_kmh=250.0, track=sc.track.replace(lead_in=30.0, run_out=10.0))
    assert sc.bridge.length == 32.0 and [v.name for v in sc.train.vehicles] == ["ice_motor"]
    return sc


def _time(sc):
    return np.round(np.arange(0.0, sc.duration, sc.analysis.output_step), 10)


def pem_response(nf: int = 6) -> RandomResponse:
    """PEM-like result: a known PSD map, zero at the last frequency (outside the wavelength band)."""
    sc = scenario()
    t = _time(sc)
    rng = np.random.default_rng(7)
    freq = np.linspace(1.0, 11.0, nf)
    df = np.full(nf, freq[1] - freq[0])
    psd = rng.random((len(CHANNELS), nf, t.size)) * np.array([1e-2, 1e-3, 1e6, 1e6])[:, None, None]
    psd[:, -1, :] = 0.0
    std = np.sqrt(np.einsum("cft,f->ct", psd, df))
    mean = np.array([0.1 * np.sin(3 * t), 0.0 * t, 10.0 * np.sin(t), 78e3 + 0 * t])
    return RandomResponse(
        method="pem", time=t, channels=CHANNELS, units=UNITS, mean=mean, std=std,
        band=(float(freq[0] - df[0] / 2), float(freq[-1] + df[-1] / 2)), scenario=sc, freq=freq, df=df, psd=psd,
        types=("german_low.vertical",), provenance={"engine": "synthetic", "seconds": 0.5,
                                                   "versions": {"numpy": np.__version__}},
    )


def mc_response(n: int = 5) -> RandomResponse:
    """Monte-Carlo-like result with confidence intervals and n stored samples (n, nc, nt)."""
    pem = pem_response()
    rng = np.random.default_rng(11)
    samples = pem.mean[None] + pem.std[None] * rng.standard_normal((n, *pem.mean.shape))
    mean, std = samples.mean(axis=0), samples.std(axis=0, ddof=1)
    return RandomResponse(
        method="monte_carlo", time=pem.time, channels=CHANNELS, units=UNITS, mean=mean, std=std, band=pem.band,
        scenario=pem.scenario, std_ci=np.stack([0.8 * std, 1.2 * std]), mean_ci=np.stack([mean - std, mean + std]),
        n_samples=n, samples=samples, min_wheel_force=samples[:, 3].min(axis=1),
        provenance={"engine": "synthetic", "seed": 1, "seconds": 2.0},
    )


def time_history() -> TimeHistory:
    sc = scenario()
    t = _time(sc)
    values = {c: (i + 1) * np.cos((i + 1) * t) for i, c in enumerate(CHANNELS)}
    return TimeHistory(time=t, channels=values, units=dict(zip(CHANNELS, UNITS)), scenario=sc,
                       provenance={"engine": "synthetic", "run_time_s": 0.1, "excitation": "none"})
