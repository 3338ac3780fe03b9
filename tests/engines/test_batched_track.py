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
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.engines.batched import BatchedEngine, BatchedOptions
from tb_exudyn.engines.dense import DenseEngine
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


def _agree(got, ref) -> float:  # noqa: ANN001
    """The largest difference of sigma(t) over the channels a random input reaches, relative to the channel's
    largest sigma (the others, zero or round-off of 1e-16 on both, below 1e-12); the means as well."""
    assert got.channel_names == ref.channel_names and len(ref.channel_names) > 10
    assert any(n.startswith("track.") for n in ref.channel_names)
    scale = ref.std.max(axis=1)
    live = scale > 1e-12
    assert live.sum() > 10 and np.all(got.std[~live] < 1e-12)
    # both means Exudyn's deterministic run (the same up to its own round-off)
    mean = np.abs(ref.mean).max(axis=1)
    assert np.all(np.abs(got.mean - ref.mean).max(axis=1)[live] <= 1e-9 * mean[live])
    return float((np.abs(got.std - ref.std)[live].max(axis=1) / scale[live]).max())


def test_monte_carlo_of_a_scenario_with_a_track_on_both_linear_engines():
    """The scenario below, Monte Carlo with 2 samples (the same seed: the same profiles) on both engines:
    sigma over the samples within 1e-9 of each channel's largest (measured 1.2e-13 with 4 samples)."""
    import warnings

    from tb_exudyn import run_monte_carlo

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got, ref = (run_monte_carlo(_track_scenario(), engine=e, n_samples=2, workers=1, progress=False)
                    for e in ("batched", "dense"))
    assert _agree(got, ref) < 1e-9


def test_pem_of_a_scenario_with_a_track_on_both_linear_engines():
    """A scenario naming a track structure (the builder's track and deck as one modal body,
    tb_exudyn.system.track_bridge, the body's rail longer than the bridge: ModalBridge.carries): the Yang & Yau
    sprung mass at 180 km/h over a 10 m span, ballasted_uic60, 6 m of approach, PEM with 2 frequencies on
    the batched and on the dense engine (both means Exudyn's run: the batched engine's linear mean needs every
    axle off the body at t = 0). Reference: the dense engine. Tolerance 1e-9 of each channel's largest sigma,
    as above: the same linear model and step, round-off apart (measured 1.5e-13)."""
    import warnings

    from tb_exudyn import run_pem

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got, ref = (run_pem(_track_scenario(), engine=e, workers=1, progress=False) for e in ("batched", "dense"))
    assert _agree(got, ref) < 1e-9
