"""The batched engine with the track: a coupled bridge block (the track's modes, whose damping Phi^T C Phi
is not diagonal) integrated against the dense engine on the same LinearSystem.

Problem: ballasted_uic60, 40 supports (24 m of rail, 4 Hermite elements a bay) standing from x = 6 m to
18 m on a simply supported 12 m deck (8 Hz alone, 10 t/m, 2 % damping): the track and the deck as one
modal body of its 103 modes up to 3 kHz (tb_exudyn.system.track_model: track_on_deck, modal_track), full
damping. Three free wheels of 1000 kg on k_H = 1.4e9 N/m (tb_exudyn.system.track_wheel.wheel_on_modal_track)
at 120 km/h, starting at x = 3, 0.5 and -2 m: the last on the rigid ground before the rail until 0.06 s (a
vehicle off the "bridge", then on it), up to three contacts on the rail at once, the deck crossed by the
first; pseudo-excitation columns of a vertical irregularity at 5, 20, 40, 60 and 100 Hz; generalized-alpha
(spectral radius 0.9), h = a bay over 96 steps, 0.5 s. Channels: the contact forces, the first wheel's
displacement and acceleration, the deck's mid-span displacement and acceleration (its station shape in
the track's modes).

Reference: the dense engine (tb_exudyn.engines.dense: one LU of the whole system per step, none of the
batched engine's structure). The two integrate the same step exactly and differ only by round-off: the
batched engine integrates the constant block beta' M + gamma' D0 + K0 in the basis of its eigenvectors with
K0 (or inverts it once) and solves the contacts by Woodbury, where the dense engine factorises the full
matrix at every step. Tolerance: the issue's 1e-9 of each channel's largest sigma (sigma(t)^2 the sum of
|Y|^2 over the columns), far above the round-off (measured 1.5e-13 in the eigenbasis, 2.6e-14 without)
and far below any modelling difference (the modal damping's diagonal alone moves the force by 18 %).

The tests at the end run a scenario naming a track structure through the methods (PEM, Monte Carlo) on
the batched, the dense and the Exudyn engine (the reference: the track and the deck one ObjectGenericODE2
with the full damping matrix), each run once and shared (``_pem``, ``_monte_carlo``).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tb_exudyn.engines.batched import BatchedEngine, BatchedOptions
from tb_exudyn.engines.dense import DenseEngine, DenseOptions
from tb_exudyn.scenario.track_structure import load_track_structure
from tb_exudyn.structure import simply_supported_modes
from tb_exudyn.system.channels import Channel, output_map
from tb_exudyn.system.columns import HarmonicColumns
from tb_exudyn.system.components import find_components
from tb_exudyn.system.conventions import run_steps
from tb_exudyn.system.track_model import modal_track, track_model, track_on_deck
from tb_exudyn.system.track_wheel import wheel_on_modal_track
from ..recording import KeepAll as _Keep

M_W, K_H, V, STARTS = 1000.0, 1.4e9, 120.0 / 3.6, (3.0, 0.5, -2.0)
FREQS = np.array([5.0, 20.0, 40.0, 60.0, 100.0])


@pytest.fixture(scope="module")
def case():
    structure = load_track_structure("ballasted_uic60")
    span, mass = 12.0, 1.0e4
    ei = (2 * np.pi * 8.0 / (np.pi / span) ** 2) ** 2 * mass
    deck = simply_supported_modes([span], ei, 1e3 * ei, 1e3 * ei, mass, mass, 0.02, 130.0)
    fe = track_on_deck(track_model(structure, 40, elements_per_bay=4), deck, 6.0)
    track = modal_track(fe, max_frequency=3000.0)
    lin = wheel_on_modal_track(track, M_W, K_H, V, STARTS)
    mid = deck.rail_shapes(np.array([span / 2])).z @ track.modes[fe.deck_dofs]  # (1, n_modes)
    stations = np.zeros((1, 3, track.bridge.n_modes))
    stations[0, 1] = mid[0]
    channels = [Channel(f"wheel{i}.force_z", "N", "contact", i) for i in range(len(STARTS))]
    channels += [Channel("wheel0.z", "m", "node", 0, 2, 0), Channel("wheel0.az", "m/s2", "node", 0, 2, 2),
                 Channel("deck.mid.z", "m", "bridge", 0, 1, 0), Channel("deck.mid.az", "m/s2", "bridge", 0, 1, 2)]
    om = output_map(channels, lambda node: lin.wheel[6 * node:6 * node + 6], stations)
    m = FREQS.size
    source = HarmonicColumns(kinds=np.zeros(m, int), omega=2 * np.pi * FREQS / V, amplitude=np.ones(m),
                             units=("angle",) * m, scale=np.ones(m), type_index=np.zeros(m, int),
                             freq_index=np.arange(m), df=np.ones(m), n_types=1)
    h = structure.spacing / V / 96
    steps = run_steps(0.5, h, 2 * h)
    return track, lin, om, source, steps


def _run(cls, case, options=None) -> np.ndarray:
    """(n_channels, m, n_t) every output of every column."""
    _, lin, om, source, steps = case
    return cls.on_system(lin, steps, 0.9, om, options).integrate(source, _Keep(steps.n_outputs))["Y"]


@pytest.mark.parametrize("basis", [True, False], ids=["eigenbasis", "as_given"])
def test_batched_against_dense_on_the_track_on_a_deck(case, basis, monkeypatch):
    """``basis``: the coupled block in the basis where A0_b^-1 K0_b is diagonal (the default), or as given
    (tb_exudyn.engines.batched.coupled)."""
    from tb_exudyn.engines.batched import coupled

    monkeypatch.setattr(coupled, "DIAGONAL_STIFFNESS_BASIS", basis)
    track, lin, _, _, steps = case
    assert track.bridge.n_modes == 103 and not np.allclose(track.damping, np.diag(np.diag(track.damping)))
    (comp,) = [c for c in find_components(lin, steps.output_times) if c.n_bridge]
    assert comp.coupled and comp.n_bridge == 103
    described = BatchedEngine.on_system(lin, steps, 0.9, case[2]).describe()["components"]
    assert [c.get("coupled_bridge", False) for c in described] == [True]
    got, ref = _run(BatchedEngine, case), _run(DenseEngine, case)
    sigma_ref = np.sqrt(np.sum(np.abs(ref) ** 2, axis=1))  # (n_channels, n_t)
    sigma_got = np.sqrt(np.sum(np.abs(got) ** 2, axis=1))
    assert np.all(sigma_ref.max(axis=1) > 0)
    err = np.abs(sigma_got - sigma_ref).max(axis=1) / sigma_ref.max(axis=1)
    assert err.max() < 1e-9, err
    # and each column's complex output, not only the sums
    assert np.all(np.abs(got - ref).max(axis=(1, 2)) < 1e-9 * np.abs(ref).max(axis=(1, 2)))


def test_the_coupled_block_in_float32(case):
    """The same in float32 (PEM's grid-error midpoints take it by default): within BatchedOptions'
    stated 1e-5 of each channel's largest sigma of float64 (measured 2e-6)."""
    ref, got = _run(BatchedEngine, case), _run(BatchedEngine, case, BatchedOptions(precision="float32"))
    sigma_ref = np.sqrt(np.sum(np.abs(ref) ** 2, axis=1))
    sigma_got = np.sqrt(np.sum(np.abs(got) ** 2, axis=1))
    err = np.abs(sigma_got - sigma_ref).max(axis=1) / sigma_ref.max(axis=1)
    assert err.max() < 1e-5, err


def test_a_coupled_track_block_takes_the_numpy_step_without_loading_numba(case, monkeypatch):
    """With only coupled components, the compiled step is not used: Numba is not loaded (issue 49: a
    run loads only the compiled code it runs); the numbers are the numpy step's (the same code path)."""
    from tb_exudyn import jit

    def refuse(name):  # noqa: ANN001, ANN202
        raise AssertionError(f"jit.load({name!r}) for a coupled track block")

    ref = _run(BatchedEngine, case, BatchedOptions(step="numpy"))
    monkeypatch.setattr(jit, "load", refuse)
    got = _run(BatchedEngine, case, BatchedOptions(step="compiled"))
    assert np.array_equal(got, ref)


def test_the_gravity_column_on_a_coupled_block(case):
    """The linear mean's gravity column (tb_exudyn.system.columns.StaticLoadColumns: rows' input f_s, a
    constant generalised force F_c) on the coupled block, the numpy step: the three wheels standing on the
    rigid ground before the rail at t = 0 (statically compressed by their weight, the track unloaded), then
    rolling onto it. Reference: the same deviation equation M d'' + D(t) d' + K(t) d = F_c - P(t)^T f_s
    from rest, integrated by the dense engine's step on full matrices (DenseEngine._run, as its own linear
    mean does), written out here. Tolerance 1e-9 of each channel's largest value, as above (measured
    8e-13 on the deck's acceleration, 3e-14 elsewhere)."""
    from tb_exudyn.system.columns import static_load_columns

    track, _, om, _, steps = case
    lin = wheel_on_modal_track(track, M_W, K_H, V, (-0.5, -3.0, -5.5))
    static = np.zeros(lin.n)
    static[lin.wheel[2::6]] = -M_W * 9.81 / K_H  # each wheel's z on its Hertz spring
    assert np.array_equal(lin.wheel, case[1].wheel)  # the case's output map holds (the same coordinates)
    source = static_load_columns(lin, static)
    got = BatchedEngine.on_system(lin, steps, 0.9, om).integrate(source, _Keep(steps.n_outputs))["Y"][:, 0]
    dense = DenseEngine.on_system(lin, steps, 0.9, om)
    cp, ci = lin.coupling, np.concatenate((lin.bridge, lin.wheel))
    r = (source.row_force / lin.k)[:, None].astype(complex)  # k r = f_s: the rows' force at rest

    def forcing(t):  # noqa: ANN001, ANN202
        st, K, D = dense._matrices(lin, t)
        F = source.force.astype(complex)[:, None].copy()
        F[ci] -= st.B.T @ source.row_force[:, None]
        return st, K, D, None, F

    def forces(st, q, v, inputs):  # noqa: ANN001, ANN202
        return cp.contact_law(st, q[ci], v[ci], r, np.zeros_like(r))

    keep = _Keep(steps.n_outputs)
    dense._run(forcing, forces, np.zeros((lin.n, 1), dtype=complex), keep, np.arange(len(om.names)), lin)
    ref = keep.Y[:, 0]
    scale = np.abs(ref).max(axis=1)
    assert np.all(scale > 0)
    err = np.abs(got - ref).max(axis=1) / scale
    assert np.all(err < 1e-9), err


def _track_scenario():  # noqa: ANN202
    from tb_exudyn import load_scenario

    sc = load_scenario("yang_yau_sprung_mass")
    return sc.replace(bridge=sc.bridge.replace(track_height=1.0, spans=(10.0,)),
                      track=sc.track.replace(structure="ballasted_uic60", lead_in=6.0, taper_length=3.0, run_out=0.0),
                      analysis=sc.analysis.replace(n_freq=2, channels=("car1.*", "track.span1.mid.*",
                                                                       "bridge.span1.mid.*"))).replace(speed_kmh=180.0)


#: PEM's grid on the scenario: 24 and 48 Hz (linear, the band's ends included), in the band where the track and
#: the point contact differ (20-50 Hz, below the P2 resonance near 50 Hz); the spectrum's band (wavelengths
#: 1-120 m) ends at 50 Hz at 180 km/h
PEM_BAND = {"freq_min": 24.0, "freq_max": 48.0, "n_freq": 2}


@functools.lru_cache(maxsize=None)
def _pem(engine: str):  # noqa: ANN202
    """PEM of the track scenario on ``engine``, once per session (shared by the tests below): the dense engine
    with its linear mean (DenseOptions(mean="linear")), the others with their default options (the batched
    engine's mean is then Exudyn's deterministic run: its linear mean needs every axle off the body at t = 0)."""
    import warnings

    from tb_exudyn import run_pem

    sc = _track_scenario()
    sc = sc.replace(analysis=sc.analysis.replace(**PEM_BAND))
    options = DenseOptions(mean="linear") if engine == "dense" else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_pem(sc, engine=engine, options=options, workers=1, progress=False, psd_channels="all")


@functools.lru_cache(maxsize=None)
def _monte_carlo(engine: str):  # noqa: ANN202
    """Monte Carlo of the track scenario with 2 samples (seed 3: the same profiles on every engine), once."""
    import warnings

    from tb_exudyn import run_monte_carlo

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_monte_carlo(_track_scenario(), engine=engine, n_samples=2, seed=3, workers=1, progress=False)


def _live(ref) -> np.ndarray:  # noqa: ANN001
    """The channels a random input reaches (the others, zero or round-off of 1e-16, below 1e-12)."""
    assert len(ref.channel_names) > 10 and any(n.startswith("track.") for n in ref.channel_names)
    live = ref.std.max(axis=1) > 1e-12
    assert live.sum() > 10
    return live


def _agree(got, ref, mean: float = 1e-9) -> float:  # noqa: ANN001
    """The largest difference of sigma(t) over the channels a random input reaches, relative to the channel's
    largest sigma (the others below 1e-12 on both); the means within ``mean`` of each channel's largest."""
    assert got.channel_names == ref.channel_names and np.array_equal(got.time, ref.time)
    live = _live(ref)
    assert np.all(got.std[~live] < 1e-12)
    largest = np.abs(ref.mean).max(axis=1)
    assert np.all(np.abs(got.mean - ref.mean).max(axis=1)[live] <= mean * largest[live])
    return float((np.abs(got.std - ref.std)[live].max(axis=1) / ref.std.max(axis=1)[live]).max())


def test_monte_carlo_of_a_scenario_with_a_track_on_both_linear_engines():
    """The scenario below, Monte Carlo with 2 samples (the same seed: the same profiles) on both engines:
    sigma over the samples within 1e-9 of each channel's largest (measured 1.2e-13 with 4 samples); the
    means both Exudyn's deterministic run plus the samples' mean deviation."""
    assert _agree(_monte_carlo("batched"), _monte_carlo("dense")) < 1e-9


def test_pem_of_a_scenario_with_a_track_on_both_linear_engines():
    """A scenario naming a track structure (the builder's track and deck as one modal body,
    tb_exudyn.system.track_bridge, the body's rail longer than the bridge: ModalBridge.carries): the Yang & Yau
    sprung mass at 180 km/h over a 10 m span, ballasted_uic60, 6 m of approach, PEM at 24 and 48 Hz on
    the batched and on the dense engine. Reference: the dense engine. Tolerance 1e-9 of each channel's largest
    sigma, as above: the same linear model and step, round-off apart (measured 1.5e-13). The means differ
    (the dense engine's linear mean against Exudyn's run): the next test."""
    assert _agree(_pem("batched"), _pem("dense"), mean=np.inf) < 1e-9


def _groups(names) -> dict[str, np.ndarray]:  # noqa: ANN001
    """The channel groups of the acceptance: the deck, the track (rail, sleeper, pad, ballast), the contact force."""
    names = np.asarray(names)
    deck = np.array([n.startswith("bridge.") or ".deck." in n for n in names])
    force = np.array([n.startswith("car") and n.endswith(".force_z") for n in names])
    track = np.array([n.startswith("track.") for n in names]) & ~deck
    assert deck.any() and track.any() and force.sum() == 1
    return {"deck": deck, "track": track, "contact force": force}


@pytest.mark.exudyn
def test_pem_of_a_scenario_with_a_track_on_the_exudyn_engine():
    """The scenario and grid above on the Exudyn engine (the reference: two Exudyn runs per frequency from
    rest, the cosine and the sine input at the working amplitude 1e-4 m; the track and the deck one
    ObjectGenericODE2 with the full damping matrix Phi^T C Phi) against the batched engine (issue 47: the
    engines agree within 1e-4 of max sigma).

    Both integrate the same model with the same scheme: Exudyn's generalized-alpha at the scenario's step
    (1 ms) and spectral radius (0.9), which the batched engine implements (engines/alpha.py,
    tests/engines/test_batched.py), so the time step needs no convergence study; the sprung mass has no
    rotations, so the model is linear and the amplitude does not matter. What remains is Exudyn's Newton
    tolerance (relative 1e-8 of the residual): measured 4.8e-8 on the rail's acceleration, 1.0e-9 on the deck
    and 2.3e-10 on the contact force (Newton at 1e-10 / 1e-8 N: 4e-10, 2e-11, 4e-12). Tolerance 1e-6 of each
    channel's largest sigma, as the batched engine's other tests against Exudyn (the issue's 1e-4 is looser);
    and each frequency's PSD within 1e-6 of its own largest value (each column alone, not hidden under the
    other's weight; measured 1.2e-7, the PSD's float32 storage included). The Exudyn body's damping cut to its
    diagonal moves the rail's sigma by 2.9 %, the deck's by 7e-4 and the force's by 1e-4 (measured): the test
    sees the full matrix. The means are both Exudyn's deterministic run (round-off apart: 1e-9)."""
    ref, got = _pem("exudyn"), _pem("batched")
    assert ref.provenance["engine"] == "exudyn" and got.provenance["mean_engine"].startswith("exudyn")
    live = _live(ref)
    err = np.abs(got.std - ref.std).max(axis=1) / np.maximum(ref.std.max(axis=1), 1e-300)
    worst = {g: float(err[m & live].max()) for g, m in _groups(ref.channel_names).items()}
    assert max(worst.values()) < 1e-6 and _agree(got, ref) < 1e-6, worst
    psd_ref, psd_got = np.asarray(ref.psd, dtype=float), np.asarray(got.psd, dtype=float)  # (channel, f, t)
    assert psd_ref.shape[:2] == (len(ref.channel_names), 2)
    scale = psd_ref.max(axis=2)  # each channel's and frequency's largest PSD value
    reached = live[:, None] & (scale > 1e-12 * scale.max(axis=1, keepdims=True))
    assert np.all(reached.sum(axis=0) > 10)  # each column reaches the deck, the track and the car
    rel = np.abs(psd_got - psd_ref).max(axis=2) / np.where(reached, scale, 1.0)
    assert np.all(rel[reached] < 1e-6), rel.max()


@pytest.mark.exudyn
def test_the_deterministic_runs_mean_on_the_track_against_the_dense_engines_linear_mean():
    """The mean of the run above (gravity, the static state on the track at t = 0, no irregularity): Exudyn's
    deterministic run (the Exudyn engine's mean, and the batched engine's on the track) against the dense
    engine's linear mean (the linear model about the same static state, the dead load integrated by its own
    dense step from there: tb_exudyn.engines.dense), the wheel standing on the track's body from the start.
    The model is linear (no rotations) and the scheme the same, so Newton's tolerance is what remains: measured
    1.4e-10 of the contact force's largest mean (56.6 kN), 8e-8 of every channel's largest |mean| at most
    (the rail's acceleration, whose mean is the small dynamic part of the run). Tolerance 1e-8 on the contact
    force, 1e-5 elsewhere (as the Exudyn Monte Carlo's test for the same reason, tests/engines/test_batched_mc.py)."""
    ref, got = _pem("exudyn"), _pem("dense")
    assert got.provenance["mean_engine"].startswith("dense")
    largest = np.abs(ref.mean).max(axis=1)
    err = np.abs(got.mean - ref.mean).max(axis=1) / np.maximum(largest, 1e-300)
    groups = _groups(ref.channel_names)
    live = _live(ref)
    assert float(err[groups["contact force"]].max()) < 1e-8, err[groups["contact force"]]
    assert float(err[live].max()) < 1e-5, err.max()


@pytest.mark.exudyn
def test_monte_carlo_of_a_scenario_with_a_track_on_the_exudyn_engine():
    """Monte Carlo above on the Exudyn engine (each sample one run of the full model with gravity from the
    static state, the sampled profile itself) against the batched engine's linear samples (the same seed, the
    same profiles). The same model and scheme: Newton's tolerance remains (relative 1e-8 of a residual that
    includes the 56 kN weight). Tolerance 1e-6 of each channel's largest sigma and mean (measured 1.3e-9 and
    3.1e-9)."""
    ref, got = _monte_carlo("exudyn"), _monte_carlo("batched")
    assert ref.method == "monte_carlo" and got.method == "monte_carlo_linear"
    assert _agree(got, ref, mean=1e-6) < 1e-6


def test_the_rail_under_each_wheel_on_both_linear_engines(case):
    """The rail channels (issue 47: the rail's displacement and acceleration under each wheel, a moving output
    row S(t) q, tb_exudyn.system.channels.rail_channels) of the case above: each wheel's rail displacement and
    acceleration, the third wheel on the rigid ground before the rail until x = 0 (t = 0.06 s).

    1. The batched engine against the dense engine: within 1e-9 of each channel's largest sigma and per
       column (the same step, round-off apart, as above; measured 4.6e-14).
    2. An identity of the model on every column and output time, independent of how the channel is formed:
       the contact is a spring k_H with no damper and no left-out-modes' flexibility in series
       (wheel_on_modal_track), delta = S(t) q + r - z_w, F = k_H delta, so the rail under the wheel is
       S q = F / k_H - r + z_w, F the contact-force channel, z_w the wheel's displacement channel and r the
       irregularity at the wheel (the columns' own input, HarmonicColumns.contact_inputs). Tolerance 1e-9 of
       the rail channel's largest value: the terms are all of the rail's order (per unit irregularity: r 1,
       F / k_H up to 1, the wheel up to 4.1 and the rail up to 3.1), so only round-off remains (measured
       2.4e-14 batched, 1.4e-15 dense; the first wheel's rail in the second's identity misses by 1.8).
    3. The third wheel's rail channels are exactly 0 while it is on the rigid line (x < 0) and not after."""
    _, lin, _, source, steps = case
    n_w = len(STARTS)
    channels = [Channel(f"wheel{i}.force_z", "N", "contact", i) for i in range(n_w)]
    channels += [Channel(f"wheel{i}.z", "m", "node", i, 2, 0) for i in range(n_w)]
    channels += [Channel(f"wheel{i}.rail.{q}_z", u, "rail", i, 0, o) for i in range(n_w)
                 for q, u, o in (("disp", "m", 0), ("acc", "m/s^2", 2))]
    om = output_map(channels, lambda node: lin.wheel[6 * node:6 * node + 6], np.zeros((0, 3, lin.bridge.size)))
    rail = (case[0], lin, om, source, steps)
    got, ref = _run(BatchedEngine, rail), _run(DenseEngine, rail)
    sigma_ref = np.sqrt(np.sum(np.abs(ref) ** 2, axis=1))
    sigma_got = np.sqrt(np.sum(np.abs(got) ** 2, axis=1))
    assert np.all(sigma_ref.max(axis=1) > 0)
    err = np.abs(sigma_got - sigma_ref).max(axis=1) / sigma_ref.max(axis=1)
    assert err.max() < 1e-9, err
    assert np.all(np.abs(got - ref).max(axis=(1, 2)) < 1e-9 * np.abs(ref).max(axis=(1, 2)))
    cp = lin.coupling
    r = np.stack([source.contact_inputs(cp, float(t))[0] for t in steps.output_times], axis=-1)  # (n_w, m, n_t)
    for Y in (got, ref):
        disp = Y[2 * n_w::2]
        identity = Y[:n_w] / K_H - r + Y[n_w:2 * n_w]
        scale = np.abs(disp).max(axis=(1, 2))
        assert np.all(np.abs(disp - identity).max(axis=(1, 2)) < 1e-9 * scale), np.abs(disp - identity).max(axis=(1, 2)) / scale
    x3 = STARTS[2] + V * steps.output_times
    off = x3 < 0.0
    assert off.sum() > 10 and np.all(got[-2:][:, :, off] == 0) and np.all(ref[-2:][:, :, off] == 0)
    assert np.all(np.abs(got[-2:][:, :, ~off]).max(axis=1) > 0)
