"""A bridge given by its modes (``kind = "modal_table"``, docs/modal_bridge.md), as an engineer brings it
from another FE program: the tables are written here, read back by the scenario loader, run, and the
run is checked against a closed form.

The bridge: a simply supported 20 m span, m = 1e4 kg/m, first frequency 5 Hz, undamped, i.e. its
vertical modes j = 1 ... 4 (5, 20, 45, 80 Hz), shapes sqrt(2 / (m L)) sin(j pi x / L) (mass-normalised:
modal_mass = 1), written at stations every L / 40 with their slopes into OUT/bridge/modes.csv and
shapes.csv, beside OUT/bridge/bridge.toml (kind = "modal_table", file names relative to it). The
scenario OUT/scenario.toml names that bridge by its path: a constant 100 kN force crossing it
(``moving_force_100kn``) at speed parameter alpha = c / (2 f1 L) = 1 (200 m/s) and 0.2 (40 m/s).

The check: the midspan deflection of the deterministic run (Exudyn engine) against Fryba's modal closed
form with the same four modes (Vibration of Solids and Structures under Moving Loads, ch. 1;
docs/references.md, validation case 2), during the crossing and in the free vibration after it; the
script fails (exit 1) if the error exceeds 1e-3 of the peak (measured: 4e-5 at dt = 2e-4 s, 1e-5 at
dt = 1e-4 s, as the FE bridge's in tests/builder/test_builder_fryba.py). Writes OUT/comparison.txt and the
runs (OUT/alpha_<a>/det).

    python examples/imported_modal_bridge.py [--quick] [--out DIR]

Full setting: both speeds at dt = 1e-4 s (a few seconds). ``--quick``: alpha = 1 only, dt = 2e-4 s.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

import tb_exudyn as tbx

NAME = "imported_modal_bridge"
L, MU, F1, P = 20.0, 1.0e4, 5.0, 1.0e5  # span [m], mass [kg/m], first frequency [Hz], force [N]
EI = MU * (2 * math.pi * F1 / (math.pi / L) ** 2) ** 2
N_MODES = 4
LEAD = 2.0
STATIONS = 41
#: of the peak: 25 times the error measured at dt = 2e-4 s (4e-5: generalized-alpha's period error on the 80 Hz
#: mode; the tables' interpolation adds 1e-6), far below what a shape off by its normalisation would give
TOLERANCE = 1e-3


def write_tables(folder: Path) -> Path:
    """modes.csv, shapes.csv and bridge.toml of the span's vertical modes; returns bridge.toml."""
    folder.mkdir(parents=True, exist_ok=True)
    w1 = (math.pi / L) ** 2 * math.sqrt(EI / MU)
    rows = ["# simply supported 20 m span, m = 1e4 kg/m: the closed-form vertical modes, mass-normalised",
            "mode,frequency_hz,damping_ratio,type,modal_mass"]
    rows += [f"{j},{j * j * w1 / (2 * math.pi)!r},0.0,vertical,1.0" for j in range(1, N_MODES + 1)]
    (folder / "modes.csv").write_text("\n".join(rows) + "\n")
    amp = math.sqrt(2.0 / (MU * L))
    cols = ["x"] + [f"{c}{j}" for j in range(1, N_MODES + 1) for c in ("y", "z", "rx")]
    cols += [f"d{c}{j}" for j in range(1, N_MODES + 1) for c in ("y", "z", "rx")]
    lines = ["# at the track line: x [m]; y, z [m], rx [rad] per unit modal coordinate; d*: slopes [1/m]", ",".join(cols)]
    for x in np.linspace(0.0, L, STATIONS):
        k = np.arange(1, N_MODES + 1) * math.pi / L
        z, dz = amp * np.sin(k * x), amp * k * np.cos(k * x)
        vals = [x] + [v for zj in z for v in (0.0, zj, 0.0)] + [v for dzj in dz for v in (0.0, dzj, 0.0)]
        lines.append(",".join(repr(float(v)) for v in vals))
    (folder / "shapes.csv").write_text("\n".join(lines) + "\n")
    toml = folder / "bridge.toml"
    toml.write_text('kind = "modal_table"\nname = "span_20m_modes"\nspans = [20.0]\nmodes = "modes.csv"\n'
                    'shapes = "shapes.csv"\ndescription = "20 m simply supported span, its first four vertical '
                    'modes (closed form) as tables"\n')
    return toml


def write_scenario(out: Path, speed: float, dt: float) -> Path:
    text = (f'name = "imported_span"\nspeed_kmh = {speed * 3.6!r}\nbridge = "bridge/bridge.toml"\n\n'
            '[train]\nvehicles = ["moving_force_100kn"]\n\n'
            f'[track]\nlead_in = {LEAD!r}\nrun_out = 20.0\ntaper_length = 0.0\n\n'
            f'[analysis]\ntime_step = {dt!r}\noutput_step = {10 * dt!r}\nfreq_max = {0.1 / dt!r}\n'
            'mode_max_frequency = 100.0\nchannels = ["bridge.span1.mid.disp_z"]\n')
    path = out / "scenario.toml"
    path.write_text(text)
    return path


def fryba_midspan(t: np.ndarray, c: float) -> np.ndarray:
    """Midspan deflection (positive DOWN) of the undamped span under P entering at t = 0 with speed c,
    modes 1 ... N_MODES; after the force leaves at T = L / c each mode vibrates freely from its state."""
    w1 = (math.pi / L) ** 2 * math.sqrt(EI / MU)
    om = math.pi * c / L
    alpha = om / w1
    w0 = 2 * P * L**3 / (math.pi**4 * EI)
    T = L / c
    out = np.zeros_like(t)
    for j in range(1, N_MODES + 1):
        wj = j * j * w1

        def amp(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            if abs(j - alpha) < 1e-12:  # resonance j = alpha: the limit of the closed form
                return (w0 / (2 * j**4) * (np.sin(wj * tt) - wj * tt * np.cos(wj * tt)),
                        w0 / (2 * j**4) * wj**2 * tt * np.sin(wj * tt))
            f = w0 / (j**2 * (j**2 - alpha**2))
            return (f * (np.sin(j * om * tt) - alpha / j * np.sin(wj * tt)),
                    f * (j * om * np.cos(j * om * tt) - alpha / j * wj * np.cos(wj * tt)))

        a = np.zeros_like(t)
        during = (t >= 0) & (t <= T)
        a[during] = amp(t[during])[0]
        aT, adT = amp(np.array([T]))
        tau = t[t > T] - T
        a[t > T] = aT * np.cos(wj * tau) + adT / wj * np.sin(wj * tau)
        out += a * math.sin(j * math.pi / 2)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="alpha = 1 only, dt = 2e-4 s")
    parser.add_argument("--out", default=str(Path("examples_out") / NAME), help=f"output folder (default ./examples_out/{NAME})")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_tables(out / "bridge")
    dt = 2e-4 if args.quick else 1e-4
    lines = [f"imported modal bridge (20 m span, {N_MODES} vertical modes from tables) under a 100 kN moving force: "
             "midspan deflection against Fryba's closed form", f"time step {dt:g} s, stations every {L / (STATIONS - 1):g} m"]
    ok = True
    for alpha in (1.0,) if args.quick else (1.0, 0.2):
        c = alpha * 2 * F1 * L
        sc = tbx.load_scenario(write_scenario(out, c, dt))
        assert sc.bridge.kind == "modal_table"
        det = tbx.run_deterministic(sc)
        det.save(out / f"alpha_{alpha:g}" / "det")
        w = det["bridge.span1.mid.disp_z"]
        ref = -fryba_midspan(det.time - LEAD / c, c)
        peak = float(np.abs(ref).max())
        err = float(np.abs(w - ref).max())
        ok &= err <= TOLERANCE * peak
        lines.append(f"alpha = {alpha:g} (c = {c:g} m/s): peak {peak * 1e3:.4f} mm, run {np.abs(w).max() * 1e3:.4f} mm, "
                     f"max error {err / peak:.2e} of the peak (allowed {TOLERANCE:g})")
    text = "\n".join(lines) + "\n"
    (out / "comparison.txt").write_text(text)
    print(text, end="")
    print(f"wrote {out}")
    if not ok:
        print("the imported bridge's run is off Fryba's closed form", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
