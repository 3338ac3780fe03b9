"""The wheel on the track through the project's engines: the track's modes as the coupling's bridge
coordinates (tb_exudyn.system.track_model.modal_track: its rail shapes are the rail's Hermite rows), the
wheel-rail contact one penalty row of the coupling (tb_exudyn.system.track_wheel.wheel_on_modal_track),
integrated by the dense and the batched engines on the hand-built LinearSystem.

Problem: ballasted_uic60 on rigid ground, 40 supports (24 m), its 99 modes up to 3 kHz; a free half
wheelset of 1000 kg on k_H = 1.4e9 N/m at 120 km/h from x = 4 m, pseudo-excitation columns of a vertical
irregularity at 5, 20, 40, 60 and 100 Hz; generalized-alpha (spectral radius 0.9), a bay over 96 steps;
the PSD per unit irregularity PSD is the time average of |F / r|^2 over 10 whole bays after 0.3 s.

References: (1) the roughness-excitation formula 1 / |alpha_w + alpha_H + alpha_r|^2 with the moving-load
receptance (written in tests/system/test_track_wheel.py, a wavenumber integral); measured within 0.4 %
(dense engine, the track's full damping). (2) The batched engine against the dense one on the same
system: their contact forces within 1e-9 of the largest (measured 1e-13), with the track's full damping (a
coupled bridge block: tests/engines/test_batched_track.py) and with modal damping (its diagonal only).
Tolerance of (1): 2 %, as the wheel-on-track test (the discrete supports' bay average of alpha_r,
amplified near P2) plus the modes above 3 kHz left out (0.2 % of the rail's receptance, formula of
docs/track.md).
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.engines.batched import BatchedEngine
from tb_exudyn.engines.dense import DenseEngine
from tb_exudyn.scenario.track_structure import load_track_structure
from tb_exudyn.system.channels import Channel, output_map
from tb_exudyn.system.columns import HarmonicColumns
from tb_exudyn.system.conventions import run_steps
from tb_exudyn.system.track_model import modal_track, track_model
from tb_exudyn.system.track_wheel import wheel_on_modal_track

from .test_track_wheel import moving_receptance
from ..recording import KeepAll as _Keep

M_W, K_H, V, X0, BAYS, STEPS_PER_BAY = 1000.0, 1.4e9, 120.0 / 3.6, 4.0, 10, 96
FREQS = np.array([5.0, 20.0, 40.0, 60.0, 100.0])


@pytest.fixture(scope="module")
def setup():
    structure = load_track_structure("ballasted_uic60")
    track = modal_track(track_model(structure, 40, elements_per_bay=4), max_frequency=3000.0)
    m = FREQS.size
    source = HarmonicColumns(kinds=np.zeros(m, int), omega=2 * np.pi * FREQS / V, amplitude=np.ones(m),
                             units=("angle",) * m, scale=np.ones(m), type_index=np.zeros(m, int),
                             freq_index=np.arange(m), df=np.ones(m), n_types=1)
    h = structure.spacing / V / STEPS_PER_BAY
    settle = int(np.ceil(0.3 / h / STEPS_PER_BAY)) * STEPS_PER_BAY
    steps = run_steps((settle + BAYS * STEPS_PER_BAY) * h, h, h)
    return structure, track, source, steps


def _run(engine, lin, source, steps) -> np.ndarray:
    """(n_t, m) the contact force of every column at every step."""
    om = output_map([Channel("wheel.force_z", "N", "contact", 0)], lambda node: lin.wheel,
                    np.zeros((0, 3, lin.bridge.size)))
    return engine.on_system(lin, steps, 0.9, om).integrate(source, _Keep(steps.n_outputs))["Y"][0].T


def test_dense_engine_with_the_track_against_the_moving_load_formula(setup):
    structure, track, source, steps = setup
    assert track.bridge.n_modes == 99 and not np.allclose(track.damping, np.diag(np.diag(track.damping)))
    lin = wheel_on_modal_track(track, M_W, K_H, V, X0)
    force = _run(DenseEngine, lin, source, steps)
    r = np.array([source.contact_inputs(lin.coupling, t)[0][0] for t in steps.output_times])
    psd = np.mean(np.abs(force / r)[-BAYS * STEPS_PER_BAY:] ** 2, axis=0)
    alpha_r = np.array([moving_receptance(structure, f, V) for f in FREQS])
    ref = 1.0 / np.abs(-1.0 / (M_W * (2 * np.pi * FREQS) ** 2) + 1.0 / K_H + alpha_r) ** 2
    err = psd / ref - 1.0
    assert np.abs(err).max() < 0.02, np.round(err, 4)
    got = _run(BatchedEngine, lin, source, steps)  # the track's damping as a coupled bridge block
    assert np.abs(got - force).max() < 1e-9 * np.abs(force).max()


def test_batched_against_dense_with_modal_track_damping(setup):
    structure, track, source, steps = setup
    lin = wheel_on_modal_track(track, M_W, K_H, V, X0, damping="modal")
    got = _run(BatchedEngine, lin, source, steps)
    ref = _run(DenseEngine, lin, source, steps)
    assert np.abs(got - ref).max() < 1e-9 * np.abs(ref).max()


def test_dense_engine_with_the_track_on_a_deck_against_the_fe_integrator(setup):
    """The whole chain through the coupling: the contact on the rail, the rail's supports on a 12 m simply
    supported deck (8 Hz alone) from x = 6 m, the track and the deck as one modal body (103 modes up to
    3 kHz), the dense engine; against the wheel on the same track-and-deck FE (all its DOFs) by the Newmark
    integrator of tb_exudyn.system.track_wheel (an independent integrator, no modes). The wheel crosses
    the deck during the averaged bays. Measured: within 1.7 % (60 Hz); on rigid ground the same pair
    differs by 1.4 % at 60 Hz (the modes above 3 kHz the modal form leaves out): tolerance 3 %."""
    from tb_exudyn.structure import simply_supported_modes
    from tb_exudyn.system.track_model import track_on_deck
    from tb_exudyn.system.track_wheel import wheel_on_track

    structure, _, source, steps = setup
    span, m = 12.0, 1.0e4
    ei = (2 * np.pi * 8.0 / (np.pi / span) ** 2) ** 2 * m
    deck = simply_supported_modes([span], ei, 1e3 * ei, 1e3 * ei, m, m, 0.02, 130.0)
    fe = track_on_deck(track_model(structure, 40, elements_per_bay=4), deck, 6.0)
    lin = wheel_on_modal_track(modal_track(fe, max_frequency=3000.0), M_W, K_H, V, X0)
    force = _run(DenseEngine, lin, source, steps)
    r = np.array([source.contact_inputs(lin.coupling, t)[0][0] for t in steps.output_times])
    psd = np.mean(np.abs(force / r)[-BAYS * STEPS_PER_BAY:] ** 2, axis=0)
    ref = wheel_on_track(fe, M_W, K_H, V, FREQS, X0, bays=BAYS, settle=0.3)
    err = psd / np.mean(np.abs(ref.transfer_at) ** 2, axis=0) - 1.0
    assert np.abs(err).max() < 0.03, np.round(err, 4)
