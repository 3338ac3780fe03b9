"""Two tracks on one deck (issue 29): the train on either track, deck channels along each track.

Problem: scenario 'quick' (one ICE motor car, car15, at 250 km/h over the 32 m simple_beam
single_span_32m, German low irregularities: vertical, alignment, cross-level), its girder given two
tracks at +2.5 m and -2.5 m from the girder axis, both 1.64 m above the shear centre. The girder is
symmetric about its axis (shear centre = mass centre, no added mass off the axis), so the train on
track 2 is the mirror image (y -> -y, roll, yaw and torsion -> minus themselves, left <-> right) of
the train on track 1. The irregularity processes are zero-mean Gaussian, so a mirrored process has
the same PSD: every sigma(t) of the run on track 2 equals that of its mirror channel on track 1
(lateral and torsional ones with the mirror's sign, which sigma does not see; vertical ones equal;
``track1`` <-> ``track2``, ``left`` <-> ``right``), and every mean equals its mirror channel's with
the sign of the mirror.

Reference: that symmetry, exact in exact arithmetic. Tolerance 1e-12 of each channel's max sigma:
the two runs are the same numbers with signs flipped (exact) and the left and right wheels' rows in
the other order, so only the order of sums differs (round-off, about 1e-15 relative per operation,
over some 1e4 steps; measured 4e-14). Means within 1e-9 of the channel's max |mean|: a lateral or
torsional mean is the small difference the eccentric weight leaves of terms some 1e3 times larger
(the vertical static response), so its relative round-off is that much larger (measured 1.4e-12).
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.scenario import TrackLine, load_scenario

pytestmark = pytest.mark.exudyn

TRACKS = (TrackLine(offset=2.5, height=1.64), TrackLine(offset=-2.5, height=1.64))
#: the mirror's sign of a channel's mean: lateral, roll, yaw and torsion, the lateral force, and the
#: derived ratios and indices that are odd in the mirror (a Sperling index is a magnitude: even)
_ODD_ENDINGS = ("_y", "_rx", "_rz", "force_y", "twist_3m", "unloading", "acc_y_wd")


def _scenario(on: int):
    sc = load_scenario("quick")
    bridge = sc.bridge.replace(track_offset=0.0, track_height=0.0, tracks=TRACKS)
    analysis = sc.analysis.replace(channels=("*",), n_freq=8, freq_spacing="linear")
    return sc.replace(bridge=bridge, analysis=analysis, track=sc.track.replace(on=on))


def _mirror(name: str) -> str:
    swaps = (("track1", "track2"), ("left", "right"))
    for a, b in swaps:
        name = name.replace(a, "\0").replace(b, a).replace("\0", b)
    return name


@pytest.fixture(scope="module")
def runs():
    import warnings

    from tb_exudyn.methods import run_pem

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grid's and the lightly damped bogie's warnings
        return tuple(run_pem(_scenario(on), workers=1, progress=False, engine="batched", psd_channels="key")
                     for on in (1, 2))


def test_channels_along_each_track():
    """The two-track deck has stations along each track at rail level (span1.mid.track2) besides the
    girder axis's, and the EN 1990 deck channels (acc_z_en1990, twist_3m) along each track only."""
    from tb_exudyn.builder import build_model

    model = build_model(_scenario(2), warn=False)
    names = [c.name for c in model.channels]
    assert model.bridge.track == 2 and model.bridge.n_tracks == 2
    for st in ("span1.mid", "span1.mid.track1", "span1.mid.track2"):
        assert f"bridge.{st}.acc_z" in names
    derived = model.derived_catalogue.names()
    assert "bridge.span1.mid.track1.acc_z_en1990" in derived and "bridge.span1.mid.track2.acc_z_en1990" in derived
    assert "bridge.span1.start.track2.twist_3m" in derived
    assert "bridge.span1.mid.acc_z_en1990" not in derived  # the girder axis is no track


def test_track_station_is_axis_plus_torsion_times_offset():
    """Problem: the station span1.mid.track2 against the girder axis's span1.mid of the same FE modes.
    Reference: the rigid cross-section, dy = v - h theta, dz = w + e theta (e = -2.5 m, h = 1.64 m).
    Tolerance 1e-12 of the largest shape value: both come from the same element polynomials, only
    evaluated with the offset inside (round-off)."""
    from tb_exudyn.builder import bridge_modes

    mb = bridge_modes(_scenario(1))
    names = list(mb.station_names)
    axis, track = mb.station_shapes[names.index("span1.mid")], mb.station_shapes[names.index("span1.mid.track2")]
    y, z, rx = axis
    scale = np.abs(mb.station_shapes).max()
    np.testing.assert_allclose(track[0], y - 1.64 * rx, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(track[1], z - 2.5 * rx, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(track[2], rx, rtol=0, atol=1e-12 * scale)
    # the train's rail shapes are the chosen track's
    x = np.linspace(0.0, 32.0, 9)
    on2 = mb.on_track(2)
    np.testing.assert_array_equal(on2.rail_shapes(x).z, mb.track_shapes(2, x).z)
    np.testing.assert_array_equal(mb.rail_shapes(x).z, mb.track_shapes(1, x).z)


def test_second_track_mirrors_the_first(runs):
    """Module docstring: every sigma(t) on track 2 equals its mirror channel's on track 1 within 1e-12
    of its max sigma, every mean within 1e-9 of its max |mean| with the mirror's sign; and the mirror
    is not trivial (the lateral and torsional responses of the two tracks' stations differ)."""
    r1, r2 = runs
    names = list(r1.channels)
    assert names == list(r2.channels)
    for i, name in enumerate(names):
        j = names.index(_mirror(name))
        top = max(float(np.max(r1.std[i])), 1e-300)
        assert np.max(np.abs(r2.std[j] - r1.std[i])) <= 1e-12 * top, name
        sign = -1.0 if name.endswith(_ODD_ENDINGS) and not name.endswith("sperling_y") else 1.0
        top_mean = max(float(np.max(np.abs(r1.mean[i]))), 1e-300)
        assert np.max(np.abs(r2.mean[j] - sign * r1.mean[i])) <= 1e-9 * top_mean, name
    # not a tautology: the train on track 1 shakes track 1's rail more than track 2's
    a, b = names.index("bridge.span1.mid.track1.acc_z"), names.index("bridge.span1.mid.track2.acc_z")
    assert np.max(r1.std[a]) > 1.01 * np.max(r1.std[b])


def test_modes_name_the_train_track():
    """`tb-exudyn modes` (builder.system_modes): the table's heading says which track the train is on."""
    from tb_exudyn.builder.system_modes import system_modes

    text = system_modes(_scenario(2)).text().splitlines()[0]
    assert "the train on track 2 of 2 (offset -2.5 m, rail level 1.64 m)" in text
