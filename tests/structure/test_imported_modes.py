"""The imported modal bridge (``kind = "modal_table"``, tb_exudyn.structure.imported): its tables, its
interpolation between stations and the round trip of our own FE's modes through the tables.

References: the FE ModalBridge of the same bridge (the round trip: the tables hold each girder element's
end values and slopes, so the Hermite cubic reproduces the element's own polynomial); polynomials and
sines written in the tests, with the error bound of cubic Hermite interpolation.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn.errors import ScenarioError
from tb_exudyn.scenario import load_bridge, load_scenario
from tb_exudyn.scenario.io import scenario_from_dict, with_settings
from tb_exudyn.scenario.model import ModalTable
from tb_exudyn.structure import StructureError, export_modes, modal_bridge
from tb_exudyn.structure.imported import read_shapes

L = 20.0


def _write(path: Path, header: list[str], rows) -> str:  # noqa: ANN001
    lines = [",".join(header)] + [",".join(repr(float(v)) if not isinstance(v, str) else v for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def _modes_csv(tmp: Path, freqs, name: str = "modes.csv", modal_mass: float = 1.0) -> str:  # noqa: ANN001
    return _write(tmp / name, ["mode", "frequency_hz", "damping_ratio", "type", "modal_mass"],
                  [[str(k + 1), f, 0.02, "vertical", modal_mass] for k, f in enumerate(freqs)])


def _shapes_csv(tmp: Path, x: np.ndarray, z: np.ndarray, dz: np.ndarray | None = None) -> str:
    """One mode: vertical shape z (lateral and twist zero), optionally its slopes."""
    header = ["x", "y1", "z1", "rx1"] + (["dy1", "dz1", "drx1"] if dz is not None else [])
    rows = [[xi, 0.0, zi, 0.0] + ([0.0, dzi, 0.0] if dz is not None else [])
            for xi, zi, dzi in zip(x, z, dz if dz is not None else z)]
    return _write(tmp / "shapes.csv", header, rows)


# ============================================================================ the round trip (li_zhu_2011)


@pytest.fixture(scope="module")
def exported(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("modes")
    export_modes(load_bridge("li_zhu_2011_bridge"), out, 100.0)
    return out


def test_round_trip_rail_shapes_equal_the_fe_bridge(exported):
    """Exact problem: li_zhu_2011_bridge (3 x 32 m girders on piers, track 2.5 m off the axis, 1.64 m
    above the shear centre; every mode up to 100 Hz) exported by export_modes and read back as a
    modal_table. Reference: the FE ModalBridge itself. Frequencies, damping ratios, types and station
    shapes are the same floats (written with repr); the rail shapes and their slopes, at 20 001 points
    and at every element end and span joint (where the FE takes the next element: so must the table,
    from the station given twice), agree to 1e-12 of each component's largest value: the Hermite cubic
    of an element's exact end values and slopes is that element's cubic re-expressed (round-off, 1e-15
    measured)."""
    fe = modal_bridge(load_bridge("li_zhu_2011_bridge"), 100.0)
    im = modal_bridge(load_bridge(exported / "bridge.toml"), 100.0)
    assert im.n_modes == fe.n_modes > 40
    assert np.array_equal(im.frequencies, fe.frequencies) and np.array_equal(im.damping_ratios, fe.damping_ratios)
    assert im.mode_types == fe.mode_types and im.station_names == fe.station_names
    assert np.array_equal(im.station_shapes, fe.station_shapes)
    x = np.concatenate([np.linspace(-2.0, 98.0, 20001), np.arange(0.0, 96.0 + 1e-9, 2.0), [32.0, 64.0, 96.0, 96.0001]])
    a, b = fe.rail_shapes(x), im.rail_shapes(x)
    for comp in ("y", "z", "rx", "dy", "dz", "drx"):
        p, q = getattr(a, comp), getattr(b, comp)
        assert np.max(np.abs(p - q)) <= 1e-12 * np.max(np.abs(p)), comp
    assert np.all(b.z[x > 96.0] == 0.0) and np.all(b.z[x < 0.0] == 0.0)  # off the bridge: no motion


def test_round_trip_truncation_as_the_fe_bridge(exported):
    """max_frequency and max_modes keep the same lowest modes as the FE bridge (same frequencies, the
    same shapes), and a max_frequency below the lowest mode names max_frequency (the scenario's
    analysis.mode_max_frequency once located)."""
    fe = modal_bridge(load_bridge("li_zhu_2011_bridge"), 20.0, max_modes=7)
    im = modal_bridge(load_bridge(exported / "bridge.toml"), 20.0, max_modes=7)
    assert im.n_modes == fe.n_modes == 7
    assert np.array_equal(im.frequencies, fe.frequencies)
    x = np.linspace(0.0, 96.0, 97)
    assert np.allclose(im.rail_shapes(x).z, fe.rail_shapes(x).z, rtol=0, atol=1e-12 * np.abs(fe.rail_shapes(x).z).max())
    with pytest.raises(StructureError) as err:
        modal_bridge(load_bridge(exported / "bridge.toml"), 1.0)
    assert err.value.key == "max_frequency"


@pytest.mark.exudyn
@pytest.mark.slow
def test_round_trip_sigma_of_every_channel(exported):
    """Acceptance (issue 29): the imported-modes round trip on li_zhu_2011. Exact problem: the li_zhu_2011
    scenario (ICE M+T+T+M at 220 km/h, German low irregularities) by PEM on the batched engine, its mean
    by the Exudyn deterministic run, once with the FE bridge and once with the exported tables; 12
    frequencies instead of 200 (the grid is the same for both runs, and equality, not convergence, is
    tested) and no grid-error refinement. Reference: the FE bridge's run. Tolerance: sigma(t) of every
    channel within 1e-9 of the max sigma of its kind (the channels of its unit: the acceptance line
    read per quantity, as a channel's own sigma can be 1e-4 of its kind's, where round-off is larger;
    measured 4.6e-12 of the largest sigma, 1.9e-11 of its kind's at worst); the mean within 1e-8 of its max |mean| (the Exudyn run's Newton tolerance
    enters; 1e-11 measured)."""
    pytest.importorskip("exudyn")
    from tb_exudyn.methods import run_pem

    sc = load_scenario("li_zhu_2011")
    sc = sc.replace(analysis=sc.analysis.replace(n_freq=12))
    runs = []
    for bridge in (sc.bridge, load_bridge(exported / "bridge.toml")):
        with pytest.warns(Warning):  # the lightly damped bogie yaw modes (the same in both runs)
            runs.append(run_pem(sc.replace(bridge=bridge), workers=1, progress=False, keep_psd=False,
                                grid_error=False))
    fe, im = runs
    assert fe.channels == im.channels and len(fe.channels) > 500
    assert any(c.startswith("bridge.pier1.top") for c in fe.channels)  # the stations' file's stations too
    # the scale of a channel: the largest max sigma among the channels of its unit (bridge.span1.q3.disp_y,
    # 5.8 um, is 4e-4 of the largest lateral displacement's: the tables' round-off, 1e-16 of each
    # shape component's largest value, reaches 1.5e-9 of that channel's own max sigma)
    own = fe.std.max(axis=1)
    by_unit = {u: max(own[i] for i, v in enumerate(fe.units) if v == u) for u in set(fe.units)}
    scale = np.array([by_unit[u] for u in fe.units])
    diff = np.abs(fe.std - im.std).max(axis=1)
    assert np.all(diff <= 1e-9 * scale), fe.channels[int(np.argmax(diff / np.maximum(scale, 1e-300)))]
    mscale = np.abs(fe.mean).max(axis=1)
    assert np.all(np.abs(fe.mean - im.mean).max(axis=1) <= 1e-8 * mscale)


# ============================================================================ interpolation


def test_hermite_reproduces_cubics_and_takes_kinks_at_repeated_stations(tmp_path):
    """Exact problem: a shape that is one cubic on [0, 8] and another on [8, 20], with a kink at x = 8
    (station given twice, each row with its side's slope), values and slopes given at 0, 3, 8, 8, 14, 20.
    Reference: the two cubics, written here. Tolerance 1e-13 of the largest value: cubic Hermite
    interpolation is exact for cubics; a point at x = 8 belongs to the second piece."""
    def f(x):  # noqa: ANN001, ANN202
        return np.where(x < 8.0, 0.01 * x**3 - 0.1 * x**2 + 0.5 * x, 2.72 - 0.3 * (x - 8.0) + 0.002 * (x - 8.0)**3)

    def df(x):  # noqa: ANN001, ANN202
        return np.where(x < 8.0, 0.03 * x**2 - 0.2 * x + 0.5, -0.3 + 0.006 * (x - 8.0)**2)

    xs = np.array([0.0, 3.0, 8.0, 8.0, 14.0, 20.0])
    slopes = df(xs)
    slopes[2] = 0.03 * 64 - 0.2 * 8 + 0.5  # the left piece's slope at its end
    _shapes_csv(tmp_path, xs, f(xs), slopes)
    ev = read_shapes(str(tmp_path / "shapes.csv"), 1, L)
    x = np.linspace(0.0, L, 2001)
    out = ev(x)
    assert np.max(np.abs(out.z[:, 0] - f(x))) <= 1e-13 * np.abs(f(x)).max()
    assert np.max(np.abs(out.dz[:, 0] - df(x))) <= 1e-13 * np.abs(df(x)).max()
    assert ev(np.array([8.0])).dz[0, 0] == pytest.approx(-0.3, abs=1e-14)


@pytest.mark.parametrize("with_slopes", [True, False])
def test_sine_mode_exact_at_stations_and_within_the_interpolation_bound(tmp_path, with_slopes):
    """Exact problem: the first mode of a simply supported 20 m span, A sin(pi x / L), at 17 stations
    (h = 1.25 m). Reference: the sine. At the stations the table's values come back to round-off (1e-15 A;
    a station's value is its segment's constant term, the last station's the sum of the last segment's
    coefficients). Between them: with slopes given, cubic Hermite interpolation's error bound
    h^4 / 384 max|f''''| = A (k h)^4 / 384 (k = pi / L: 3.87e-6 A; 3.85e-6 A measured, the bound is
    sharp for a sine); without slopes, the not-a-knot spline: the complete spline's bound 5/384 A (k h)^4
    (1.9e-5 A) is no theorem for the not-a-knot end conditions, so it is doubled (8.4e-6 A measured)."""
    A, k = 0.0104, math.pi / L
    xs = np.linspace(0.0, L, 17)
    h = xs[1] - xs[0]
    _shapes_csv(tmp_path, xs, A * np.sin(k * xs), A * k * np.cos(k * xs) if with_slopes else None)
    ev = read_shapes(str(tmp_path / "shapes.csv"), 1, L)
    assert np.max(np.abs(ev(xs).z[:, 0] - A * np.sin(k * xs))) <= 1e-15 * A
    x = np.linspace(0.0, L, 4001)
    err = np.max(np.abs(ev(x).z[:, 0] - A * np.sin(k * x)))
    bound = A * (k * h) ** 4 / 384 * (1.0 if with_slopes else 2 * 5.0)
    assert err <= bound, (err, bound)


def test_default_stations_are_on_the_track_line(tmp_path):
    """Without a stations file the span stations q1, mid, q3 are the track line's shapes there: for the
    sine A sin(pi x / L) over one span, A sin(pi / 4), A, A sin(3 pi / 4) (Hermite exact at stations, and
    mid is a station here; q1 and q3 within the sine's Hermite bound, 1e-6 A)."""
    A, k = 0.01, math.pi / L
    xs = np.linspace(0.0, L, 21)
    bridge = ModalTable(name="t", spans=(L,), modes=_modes_csv(tmp_path, [5.0]),
                        shapes=_shapes_csv(tmp_path, xs, A * np.sin(k * xs), A * k * np.cos(k * xs)))
    mb = modal_bridge(bridge, 100.0)
    assert mb.station_names == ("span1.q1", "span1.mid", "span1.q3")
    assert mb.station_shapes[:, 1, 0] == pytest.approx(A * np.sin(np.pi * np.array([0.25, 0.5, 0.75])), abs=1e-6 * A)
    assert mb.station_shapes[1, 1, 0] == pytest.approx(A, abs=1e-16)
    assert mb.damping_ratios[0] == 0.02 and mb.mode_types == ("vertical",)


# ============================================================================ files and their names


def test_file_names_relative_to_the_file_read(tmp_path, monkeypatch):
    """A bridge.toml names its tables relative to itself: read from another working folder, inline in a
    scenario file (relative to that file), and after a --set (the scenario read again from its plain
    form), the tables are still found."""
    d = tmp_path / "bridge"
    d.mkdir()
    xs = np.linspace(0.0, L, 9)
    _modes_csv(d, [5.0])
    _shapes_csv(d, xs, 0.01 * np.sin(math.pi * xs / L))
    (d / "bridge.toml").write_text('kind = "modal_table"\nname = "t"\nspans = [20.0]\nmodes = "modes.csv"\n'
                                   'shapes = "shapes.csv"\n')
    monkeypatch.chdir(tmp_path.parent)
    b = load_bridge(d / "bridge.toml")
    assert Path(b.modes) == (d / "modes.csv").resolve()
    data = {"name": "s", "speed_kmh": 100.0, "train": {"vehicles": ["moving_force_100kn"]},
            "bridge": {"kind": "modal_table", "name": "t", "spans": [20.0], "modes": "bridge/modes.csv",
                       "shapes": "bridge/shapes.csv"}}
    sc = scenario_from_dict(data, str(tmp_path / "scenario.toml"))
    assert Path(sc.bridge.shapes) == (d / "shapes.csv").resolve()
    sc2 = with_settings(sc, [("speed_kmh", 120.0)])
    assert modal_bridge(sc2.bridge, 100.0).n_modes == 1


def test_modes_not_mass_normalised_are_refused(tmp_path):
    """A modes file whose modal_mass is not 1 (shapes normalised to a unit maximum, say, with modal mass
    1.8e5 kg) is refused naming the file, the column and the row; within 1e-3 of 1 it is taken."""
    xs = np.linspace(0.0, L, 9)
    shapes = _shapes_csv(tmp_path, xs, np.sin(math.pi * xs / L))
    bad = ModalTable(name="t", spans=(L,), modes=_modes_csv(tmp_path, [5.0], modal_mass=1.8e5), shapes=shapes)
    with pytest.raises(ScenarioError) as err:
        modal_bridge(bad, 100.0)
    assert "modes.csv" in str(err.value) and "modal_mass[row 1]" in str(err.value)
    assert "not mass-normalised" in str(err.value)
    ok = ModalTable(name="t", spans=(L,), modes=_modes_csv(tmp_path, [5.0], "m2.csv", modal_mass=1.0005),
                    shapes=shapes)
    assert modal_bridge(ok, 100.0).n_modes == 1



@pytest.mark.parametrize("n", [2, 3, 4, 7, 30])
def test_spline_slopes_are_the_not_a_knot_spline(n):
    """Without slope columns the slopes are those of the not-a-knot cubic spline through each piece.
    Reference: scipy.interpolate.CubicSpline(bc_type='not-a-knot') (2 points: the line, 3: the parabola,
    as scipy makes them) on uneven stations and two columns; tolerance 1e-12 of the largest slope (the
    same banded system, solved by the same LAPACK routine or its equivalent)."""
    from scipy.interpolate import CubicSpline

    from tb_exudyn.structure.imported import _spline_slopes

    rng = np.random.default_rng(n)
    x = np.sort(rng.uniform(0.0, 20.0, n))
    y = np.column_stack([np.sin(x / 3.0), rng.standard_normal(n)])
    ref = CubicSpline(x, y, axis=0, bc_type="not-a-knot")(x, 1)
    assert np.max(np.abs(_spline_slopes(x, y) - ref)) <= 1e-12 * np.abs(ref).max()


@pytest.mark.exudyn
@pytest.mark.slow
def test_every_engine_and_method_runs_the_imported_bridge(tmp_path):
    """Exact problem: the quick scenario (one ICE motor car over single_span_32m at 250 km/h) with 2
    linear frequencies and two irregularity types (vertical, cross-level), once with the FE bridge and
    once with its exported tables: PEM on the Exudyn, dense and batched engines and Monte Carlo (2
    samples, batched). Reference: the FE bridge's run on the same engine. Tolerance 1e-9 of each
    channel's max sigma: the bridges agree to round-off, the Exudyn engine's Newton iteration adds its
    tolerance (1.2e-11 measured; dense and batched 1e-12, Monte Carlo 2e-12)."""
    pytest.importorskip("exudyn")
    import warnings

    from tb_exudyn.methods import run_monte_carlo, run_pem

    sc = load_scenario("quick")
    export_modes(sc.bridge, tmp_path, sc.analysis.mode_max_frequency, sc.analysis.max_modes)
    sc = sc.replace(analysis=sc.analysis.replace(n_freq=2, freq_spacing="linear"),
                    track=sc.track.replace(irregularities=("german_low.vertical", "german_low.cross_level")))
    im = sc.replace(bridge=load_bridge(tmp_path / "bridge.toml"))
    runs = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the bogie's lightly damped yaw mode, the coarse grid: both runs alike
        for engine in ("exudyn", "dense", "batched"):
            runs[engine] = [run_pem(s, workers=1, progress=False, keep_psd=False, engine=engine, grid_error=False)
                            for s in (sc, im)]
        runs["mc"] = [run_monte_carlo(s, n_samples=2, workers=1, progress=False) for s in (sc, im)]
    for name, (fe, tab) in runs.items():
        assert fe.channels == tab.channels
        scale = fe.std.max(axis=1)
        assert np.all(np.abs(fe.std - tab.std).max(axis=1) <= 1e-9 * scale), name
        assert np.any(scale > 0), name
