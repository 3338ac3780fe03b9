"""An imported modal bridge of two tracks (issue 29): our FE's modes of a two-track deck exported as
tables (a shapes file per track) and read back.

Problem: the 32 m girder of single_span_32m with two tracks, (e, h) = (2.5 m, 1.64 m) and
(-2.0 m, 1.2 m), modes up to 40 Hz; export_modes, then the modal_table read back.
References: the FE bridge itself. Its rail shapes along each track are, within each element, a cubic
(bending) plus a linear function (twist) times the track's offset and height, which the exported
element-end values and slopes reproduce exactly (docs/modal_bridge.md): tolerance 1e-12 of the
largest shape value (round-off of the shortest float texts, read back exactly, and of the Hermite
evaluation). A PEM run on track 2 (batched engine) over both bridges: sigma(t) of every channel within
1e-9 of its max sigma, the acceptance bound of the one-track round trip (measured there 3e-14).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tb_exudyn.scenario import TrackLine, load_bridge, load_scenario
from tb_exudyn.structure import export_modes, modal_bridge

TRACKS = (TrackLine(offset=2.5, height=1.64), TrackLine(offset=-2.0, height=1.2))


@pytest.fixture(scope="module")
def bridges(tmp_path_factory):
    fe = load_bridge("single_span_32m").replace(track_offset=0.0, track_height=0.0, tracks=TRACKS)
    folder = tmp_path_factory.mktemp("modes")
    written = export_modes(fe, folder, 40.0)
    assert sorted(written) == ["bridge.toml", "modes.csv", "shapes_track1.csv", "shapes_track2.csv", "stations.csv"]
    return fe, load_bridge(str(folder / "bridge.toml"))


def test_tracks_round_trip(bridges):
    fe, imported = bridges
    assert [(t.offset, t.height) for t in imported.tracks] == [(2.5, 1.64), (-2.0, 1.2)] and not imported.shapes
    a, b = modal_bridge(fe, 40.0), modal_bridge(imported, 40.0)
    assert b.n_tracks == 2 and a.station_names == b.station_names
    assert "span1.mid.track2" in b.station_names
    x = np.linspace(-1.0, 33.0, 137)
    for k in (1, 2):
        sa, sb = a.track_shapes(k, x), b.track_shapes(k, x)
        for f in ("y", "z", "rx", "dy", "dz", "drx"):
            ref = getattr(sa, f)
            assert np.max(np.abs(getattr(sb, f) - ref)) <= 1e-12 * max(np.max(np.abs(ref)), 1e-300), (k, f)
    np.testing.assert_allclose(b.station_shapes, a.station_shapes, rtol=0, atol=1e-12 * np.abs(a.station_shapes).max())


@pytest.mark.exudyn
def test_run_on_track_two_round_trip(bridges):
    from tb_exudyn.methods import run_pem

    fe, imported = bridges
    sc = load_scenario("quick")
    analysis = sc.analysis.replace(channels=("*",), n_freq=6, freq_spacing="linear", mode_max_frequency=40.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grid's and the lightly damped bogie's warnings
        ra, rb = (run_pem(sc.replace(bridge=b, analysis=analysis, track=sc.track.replace(on=2)), workers=1,
                          progress=False, engine="batched", psd_channels="key") for b in (fe, imported))
    assert list(ra.channels) == list(rb.channels)
    assert "bridge.span1.mid.track2.acc_z_en1990" in ra.channels
    top = np.max(ra.std, axis=1, keepdims=True)
    assert np.all(np.abs(rb.std - ra.std) <= 1e-9 * np.maximum(top, 1e-300))
