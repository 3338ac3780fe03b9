"""The batched engine's kernel against the dense engine, its reference: general linear rows, the
per-step input forms, the gravity column of the linear mean and float32 columns.

The hand-made system (no Exudyn): one wheelset (x, y, z, rx, ry, rz) held by primary springs and
dampers to a fixed frame, crossing a two-span modal bridge (closed-form simply supported modes, the
track 1.5 m off the girder axis) at 30 m/s; its rows are the two vertical penalty rows of
tests/system/test_creep_coupling.py and, optionally, the four creep rows of
:mod:`tb_exudyn.system.creep` (lateral creep with the gravitational stiffness, longitudinal creep
per wheel, spin and gravitational yaw moment) as general linear rows. Both engines take the same
:class:`~tb_exudyn.system.linear.LinearSystem` and Exudyn's generalized-alpha step, so they must
agree to round-off: the batched engine solves each step by Woodbury over the contact rows with the
rows' application map P and force maps F^k, F^d (docs/creep_design.md, section 4), the dense one
with one LU of the full matrix from the coupling's own Jacobians, contact law and general-row maps.
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.engines.alpha import GeneralizedAlpha
from tb_exudyn.engines.batched import BatchedEngine, BatchedOptions
from tb_exudyn.engines.batched.inputs import shared_inputs
from tb_exudyn.engines.batched.run import _Operators, _Run
from tb_exudyn.engines.batched.steps import step_block
from tb_exudyn.engines.dense import DenseEngine
from tb_exudyn.system.channels import Channel, output_map
from tb_exudyn.system.columns import HarmonicColumns, ProfileColumns, row_inputs
from tb_exudyn.system.conventions import run_steps
from tb_exudyn.system.contact_rows import ContactRows
from tb_exudyn.system.coupling import VERTICAL, WheelRailCoupling
from tb_exudyn.system.linear import LinearSystem

from ..system.test_creep_coupling import WHEEL_COORDS, _bridge, _rows
from ..recording import KeepAll as _Keep

B = 0.75
NODE = 7
SPEED = 30.0


def _system(with_creep: bool) -> LinearSystem:
    """The wheelset on its primary suspension (springs and dampers to a fixed frame at +-1 m) over
    the bridge, with or without the creep rows; the coupling's approach taper is 5 m."""
    rows = ContactRows()
    for side in (1.0, -1.0):
        rows.add(name=f"axle1.{'left' if side > 0 else 'right'}.force_z", axle=0, direction=VERTICAL,
                 rail_offset=side * B, stiffness=2e9, damping=3e5 * (1.5 + side / 4),
                 wheel_terms={(NODE, 2): 1.0, (NODE, 3): side * B}, inputs=(1.0, 0.0, side * B))
    if with_creep:
        cr = _rows()
        for i, name in enumerate(cr.rows):
            terms = [{(NODE, c): float(M[i, j]) for j, c in enumerate(WHEEL_COORDS) if M[i, j] != 0.0}
                     for M in (cr.A_w, cr.K_w, cr.C_w)]
            rows.add_linear(name=f"axle1.{name}", axle=0, wheel_application=terms[0], wheel_stiffness=terms[1],
                            wheel_damping=terms[2], rail_application=cr.A_r[i], rail_stiffness=cr.K_r[i],
                            rail_damping=cr.C_r[i])
    cp = WheelRailCoupling(_bridge(), axle_start=[-3.0], speed=SPEED, contacts=rows.layout({NODE: 0}, 6),
                           half_gauge=B, taper_length=5.0)
    nb = cp.n_bridge
    om, zeta = cp.bridge.omega, cp.bridge.damping_ratios
    m, inertia = 1500.0, np.array([800.0, 100.0, 800.0])
    kx, ky, kz, b1 = 1.2e6, 6e6, 1.1e6, 1.0  # primary springs per side (x, y, z) at y = +-b1
    Kw = np.diag([2 * kx, 2 * ky, 2 * kz, 2 * kz * b1**2, 5e5, 2 * kx * b1**2])
    Dw = 2e-3 * Kw + np.diag([0.0, 2e4, 1e4, 1e4, 0.0, 0.0])
    M = np.diag(np.concatenate((np.ones(nb), [m, m, m], inertia)))
    K0 = np.zeros((nb + 6, nb + 6))
    D0 = np.zeros_like(K0)
    K0[:nb, :nb], D0[:nb, :nb] = np.diag(om**2), np.diag(2 * zeta * om)
    K0[nb:, nb:], D0[nb:, nb:] = Kw, Dw
    return LinearSystem(M=M, K0=K0, D0=D0, bridge=np.arange(nb), wheel=nb + np.arange(6), k=cp.contacts.stiffness,
                        c=cp.contacts.damping, G=cp.contacts.wheel_map, coupling=cp, linearization="rest")


def _outputs(lin: LinearSystem):
    """Every wheelset coordinate (disp, vel, acc), the bridge at 10 and 32 m (y, z, rx rows of the
    rail shapes there: 'stations'), every contact row (penalty rows, then general rows)."""
    cp = lin.coupling
    rs = cp.bridge.rail_shapes(np.array([10.0, 32.0]))
    stations = np.stack([np.stack((rs.y[i], rs.z[i], rs.rx[i])) for i in range(2)])  # (2, 3, n_b)
    channels = [Channel(f"axle.{q}_{c}", "-", "node", NODE, j, o) for o, q in enumerate(("disp", "vel", "acc"))
                for j, c in enumerate(("x", "y", "z", "rx", "ry", "rz"))]
    channels += [Channel(f"bridge.s{s}.{q}_{c}", "-", "bridge", s, j, o) for s in range(2)
                 for o, q in enumerate(("disp", "vel", "acc")) for j, c in enumerate(("y", "z", "rx"))]
    channels += [Channel(f"row{r}", "N", "contact", r) for r in range(cp.n_contacts + cp.n_linear)]
    return output_map(channels, lambda node: lin.wheel, stations)


def _harmonic() -> HarmonicColumns:
    """Vertical, alignment and cross-level columns at spatial frequencies 0.3-3 rad/m (wavelengths
    2-21 m: the bridge's and the wheelset's modes), amplitudes of a few mm."""
    kinds = np.array([0, 1, 2, 1, 2, 0, 1])
    omega = np.array([0.3, 0.3, 0.3, 1.1, 1.7, 2.5, 3.0])
    return HarmonicColumns(kinds=kinds, omega=omega, amplitude=np.full(7, 1e-3), units=("angle",) * 7,
                           scale=np.array([2e-3, 3e-3, 1e-3, 1e-3, 5e-4, 1e-3, 4e-4]), type_index=kinds,
                           freq_index=np.arange(7), df=np.ones(7), n_types=3)


def _profiles() -> ProfileColumns:
    """Five samples of smooth random profiles of each kind on a 0.25 m grid (mm amplitudes)."""
    rng = np.random.default_rng(7)
    x = -10.0 + 0.25 * np.arange(400)
    grids = {k: sum(rng.normal(size=5)[None, :] * np.sin(w * x[:, None] + rng.uniform(0, 6, 5)[None, :]) * a
                    for w, a in ((0.4, 2e-3), (1.3, 5e-4), (2.9, 1e-4)))
             for k in ("vertical", "alignment", "cross_level")}
    return ProfileColumns(grids, -10.0, 0.25, "angle", B)


def _both(with_creep: bool, source, options=None, dense_options=None):
    lin = _system(with_creep)
    steps = run_steps(1.9, 1e-3, 1e-2)  # on the bridge from 0.1 s, across both spans by 1.6 s
    om = _outputs(lin)
    got = BatchedEngine.on_system(lin, steps, 0.9, om, options).integrate(source, _Keep(steps.n_outputs))["Y"]
    ref = DenseEngine.on_system(lin, steps, 0.9, om, dense_options).integrate(source, _Keep(steps.n_outputs))["Y"]
    return got, ref, om


def _worst(got: np.ndarray, ref: np.ndarray, om=None) -> float:  # noqa: ANN001
    """Largest over channels of max |got - ref| / max |ref| (over columns and times). With the output
    map ``om``, the wheelset's x and spin channels are checked apart and left out (the creep rows'
    common longitudinal creep couples them only with each other; no input reaches them on
    straight track): the batched engine
    drops the part no input reaches (exact zeros), the dense engine integrates it on the full
    matrices and leaves round-off (the left and right wheels' antisymmetric creep forces cancel on x
    only to round-off): below 1e-12 of the largest lateral or vertical wheelset channel of the same
    quantity (measured 1e-15)."""
    keep = np.ones(ref.shape[0], dtype=bool)
    if om is not None:
        for q in ("disp", "vel", "acc"):
            scale = max(np.abs(ref[om.names.index(f"axle.{q}_{c}")]).max() for c in ("y", "z", "rx", "rz"))
            for c in ("x", "ry"):
                i = om.names.index(f"axle.{q}_{c}")
                assert not np.any(got[i]) and np.abs(ref[i]).max() < 1e-12 * scale, (q, c)
                keep[i] = False
    scale = np.abs(ref[keep]).max(axis=(1, 2))
    return float((np.abs(got[keep] - ref[keep]).max(axis=(1, 2)) / np.where(scale > 0, scale, 1.0)).max())


@pytest.mark.parametrize("with_creep", [False, True])
def test_general_rows_batched_equals_dense(with_creep):
    """Exact problem: the hand-made wheelset over the bridge (module docstring) with harmonic
    columns of every kind, all outputs at every output time. Reference: the dense engine on the
    same linear system. Both are Exudyn's generalized-alpha step solved exactly, so the tolerance
    is round-off: 1e-9 of each channel's largest value (the stiff contact, 2e9 N/m against 1.5 t,
    amplifies the round-off of the Woodbury solve; measured about 1e-12). With the creep rows
    the outputs must differ from those without (the rows act: lateral forces, the bridge's lateral
    response) and their forces must be nonzero."""
    got, ref, om = _both(with_creep, _harmonic())
    assert np.abs(ref).max() > 0 and np.all(np.isfinite(got))
    assert _worst(got, ref, om) < 1e-9
    lateral = np.abs(ref[om.names.index("axle.disp_y")]).max()
    if with_creep:  # the creep rows carry the alignment and cross-level to the wheelset's sway
        assert lateral > 1e-6 and all(np.abs(ref[om.names.index(f"row{r}")]).max() > 0 for r in (2, 3, 4, 5))
    else:  # no row acts laterally: the sway stays at rest
        assert lateral == 0.0


def test_general_rows_with_sampled_profiles_batched_equals_dense():
    """Exact problem: as above with five sampled profiles of each kind (Monte Carlo's column source,
    two real samples per complex column). Reference: the dense engine; tolerance as above."""
    got, ref, om = _both(True, _profiles())
    assert np.abs(ref).max() > 0
    assert _worst(got, ref, om) < 1e-9


@pytest.mark.parametrize("source", [_harmonic, _profiles])
def test_per_step_input_forms_equal_the_source_definition(source):
    """Exact problem: the input forces f_in of every row (penalty and creep rows) at 60 times across
    the taper and the bridge. Reference: :func:`~tb_exudyn.system.columns.row_inputs`, the
    definition (rail inputs times the rows' value and slope weights). Tolerance 1e-12 of the
    largest input (the same products in another order)."""
    lin = _system(True)
    cp, src = lin.coupling, source()
    comp = BatchedEngine.on_system(lin, run_steps(1.9, 1e-3, 1e-2), 0.9, _outputs(lin)).components[0]
    run = _Run(_Operators(lin, GeneralizedAlpha(0.9, 1e-3), comp), np.arange(src.width), src, cp)
    maps = cp.row_maps()
    for n in np.linspace(0, 1800, 60).astype(int):
        block = step_block(cp, int(n), int(n) + 1, 1e-3, {})
        shared = shared_inputs(src, float(block.t[0]), bool(block.zero[0]), block.x[0], cp.speed)
        out = np.zeros((run.rows.size, src.width), dtype=complex)
        run.inputs(0, block, shared, out)
        ref = row_inputs(src, maps, cp, float(block.t[0]))[run.rows]
        assert np.abs(out - ref).max() <= 1e-12 * max(np.abs(ref).max(), 1e-300), n


def test_float32_columns_within_their_stated_error():
    """Exact problem: the wheelset with creep rows, harmonic columns. Reference: the same batched
    engine in float64. The float32 step rounds K0 q~ and the contact forces to 6e-8 relative; the
    step recovers the accelerations from Delta = q - q~, a small remainder of those nearly balanced
    forces, so their error is about 6e-8 (omega_n / omega)^2 of the acceleration for a mode
    omega_n driven at omega: with the contact mode at 184 Hz and inputs from 2 Hz, up to 5e-4
    (measured 4e-4, the wheelset's roll acceleration; displacements and forces 1e-4 and below).
    Tolerance 2e-3 of each channel's largest value, and the results must differ from float64
    (float32 really is used). On the reference study sigma stays within 1e-5 of each channel's
    largest sigma (docs/speed.md)."""
    lin = _system(True)
    steps = run_steps(1.9, 1e-3, 1e-2)
    om = _outputs(lin)
    f64 = BatchedEngine.on_system(lin, steps, 0.9, om).integrate(_harmonic(), _Keep(steps.n_outputs))["Y"]
    f32 = BatchedEngine.on_system(lin, steps, 0.9, om, BatchedOptions(precision="float32")).integrate(
        _harmonic(), _Keep(steps.n_outputs))["Y"]
    err = _worst(f32, f64)
    assert 1e-10 < err < 2e-3, err


def test_static_load_column_against_the_dense_mean():
    """Exact problem: the gravity column of the linear mean on the hand-made system: the static
    state u_s of the wheelset on the approach under a 150 kN axle load (its springs compressed)
    and the deviation from it as the wheel loads cross the bridge. Reference: the dense engine's
    linear mean, M d'' + D(t) d' + K(t) d = W - K(t) u_s from rest with the coupling's own
    Jacobians, written independently of the gravity column's row-force form
    (:class:`~tb_exudyn.system.columns.StaticLoadColumns`). Tolerance: round-off, 1e-9 of each
    channel's largest value."""
    from tb_exudyn.system.columns import static_load_columns

    lin = _system(True)
    cp = lin.coupling
    steps = run_steps(1.9, 1e-3, 1e-2)
    om = _outputs(lin)
    W = np.zeros(lin.n)
    W[lin.wheel[2]] = -1.5e5  # the axle load, downward
    Kc, _ = cp.jacobians(0.0)
    K_all = lin.K0.copy()
    ci = np.concatenate((lin.bridge, lin.wheel))
    K_all[np.ix_(ci, ci)] += Kc
    u_s = np.linalg.solve(K_all, W)
    got = BatchedEngine.on_system(lin, steps, 0.9, om).integrate(static_load_columns(lin, u_s), _Keep(steps.n_outputs))["Y"]
    got = got.real[:, 0]
    for i, g, order in om.node:
        if order == 0:
            got[i] += u_s[g]

    dense = DenseEngine.on_system(lin, steps, 0.9, om)

    def forcing(t):
        st, K, D = dense._matrices(lin, t)
        return st, K, D, None, (W - K @ u_s)[:, None].astype(complex)

    def forces(st, q, v, inputs):
        z = np.zeros((cp.n_contacts, 1))
        return np.concatenate((cp.contact_law(st, q[ci], v[ci], z, z), st.K_lin @ q[ci] + st.D_lin @ v[ci]))

    ref = dense._run(forcing, forces, np.zeros((lin.n, 1), dtype=complex), _Keep(steps.n_outputs),
                     np.arange(len(om.names)), lin, offset=u_s)["Y"].real[:, 0]
    assert np.abs(ref[om.names.index("row0")]).max() > 5e4  # the wheel load is carried
    assert _worst(got[:, None], ref[:, None], om) < 1e-9
