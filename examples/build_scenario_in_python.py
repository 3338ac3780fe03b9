"""A scenario built entirely in Python (no TOML): a Shinkansen-like train over a two-span beam.

Every part of the scenario is a frozen dataclass from ``tb_exudyn.scenario``: the 15-DOF car
(``Car15`` with its inertias, geometry and suspensions), the train, a two-span simply supported box
girder (``SimpleBeam``), the track irregularities and the analysis settings. Each is validated when it
is made, and ``replace`` gives a checked, modified copy (here: the speed from ``--speed``).

The car is a Shinkansen S300-like coach: vertical data from Wu & Yang, Engineering Structures 25
(2003) 251-265, as tabulated in the project's vehicle reference; the lateral and roll data, which that
source does not give, are the ICE motor car's (``models/vehicles/ice_motor.toml``) [check]. The girder
is the 32 m box girder of ``models/bridges/single_span_32m.toml``, twice.

Runs the deterministic crossing (the mean: gravity, smooth track) and the PEM sweep (German
low-interference vertical, alignment and cross-level irregularities), prints both summaries, and
writes to OUT: ``scenario.toml`` (the scenario, loadable with ``tb_exudyn.load_scenario``), ``det/``
and ``pem/`` (results), figures of a few channels (``det/figures``, ``pem/figures``) and ``report.html``.

    python examples/build_scenario_in_python.py [--quick] [--speed KMH] [--cars N] [--workers N] [--out DIR]

Full setting: three cars at 300 km/h, 40 frequencies (log-spaced over the wavelengths 1-120 m): 15 s
with the batched engine on 2 cores; with ``--engine exudyn`` (240 Exudyn runs) 10 minutes on 2 cores
shared with other jobs. ``--quick``: one car, 40 m lead-in, 5 m run-out,
4 frequencies, 2 ms time step with a softer contact: a smoke run (well under a minute), not a result.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the PSD-map script's helpers

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.scenario import (
    Analysis,
    BeamSection,
    Car15,
    Car15Geometry,
    RigidBodyInertia,
    Scenario,
    SimpleBeam,
    Suspension,
    Track,
    Train,
    WheelsetInertia,
)
from tb_exudyn.methods import summarize

from li_zhu_2011_psd_maps import add_common_arguments, run_study_pem

NAME = "build_scenario_in_python"
#: channels drawn (figures and report); the summaries list every channel
FIGURE_CHANNELS = ("bridge.span2.mid.acc_z", "bridge.span2.mid.acc_y", "car1.body.acc_y", "car1.axle1.force_y")


def shinkansen_car(name: str = "shinkansen_s300") -> Car15:
    """A Shinkansen S300-like 15-DOF coach.

    Wu & Yang (2003) give per axle (primary, both sides) 1.18e6 N/m and 3.92e4 N s/m and per bogie
    (secondary, both sides) 5.3e5 N/m and 9.02e4 N s/m: halved here, because Car15 takes values per
    side. Values marked [check] are the ICE motor car's.
    """
    return Car15(
        name=name,
        description="Shinkansen S300-like coach (vertical: Wu & Yang 2003; lateral: ICE motor car [check])",
        source="Wu Y.S., Yang Y.B., Engineering Structures 25 (2003) 251-265 (docs/references.md, vehicles)",
        notes="[check] roll and yaw inertias, all lateral suspension values, lateral spans and heights: ICE motor car",
        body=RigidBodyInertia(mass=41_750.0, inertia_roll=1.15e5, inertia_pitch=2.08e6, inertia_yaw=2.08e6),
        bogie=RigidBodyInertia(mass=3_040.0, inertia_roll=3_200.0, inertia_pitch=3_930.0, inertia_yaw=3_930.0),
        wheelset=WheelsetInertia(mass=1_780.0, inertia_roll=1_200.0),
        geometry=Car15Geometry(
            half_bogie_spacing=8.75, half_wheelbase=1.25, length=25.0,  # Wu & Yang: 17.5 m, 2.5 m, 25 m
            half_primary_span=1.0, half_secondary_span=0.95, body_cg_above_secondary=0.8,  # [check] ICE
            secondary_above_bogie_cg=0.3, bogie_cg_above_axle=-0.05, wheel_radius=0.46,  # [check] ICE
        ),
        primary=Suspension(k_z=1.18e6 / 2, c_z=3.92e4 / 2, k_y=3.0e6, c_y=0.0),     # k_y, c_y [check] ICE
        secondary=Suspension(k_z=5.3e5 / 2, c_z=9.02e4 / 2, k_y=4.8e5, c_y=3.0e4),  # k_y, c_y [check] ICE
    )


def two_span_beam() -> SimpleBeam:
    """Two simply supported 32 m box girders (the girder of single_span_32m), track 2.5 m off centre."""
    girder = BeamSection(
        E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
        mass_per_length=33_900.0,       # girder and added mass: first vertical mode 5.12 Hz
        rot_mass_per_length=383_040.5,
    )
    return SimpleBeam(
        name="two_spans_32m", spans=(32.0, 32.0), girder=girder, damping_ratio=0.05,
        track_offset=2.5, track_height=1.64, elements_per_span=16,
        description="two 32 m simply supported box girders (girder of single_span_32m)",
    )


def build(speed_kmh: float, cars: int, quick: bool) -> Scenario:
    """The scenario: ``cars`` coaches at ``speed_kmh`` over the two spans."""
    car = shinkansen_car()
    track = Track(
        irregularities=("german_low.vertical", "german_low.alignment", "german_low.cross_level"),
        wavelength_min=1.0, wavelength_max=120.0, lead_in=100.0, run_out=50.0,
    )
    analysis = Analysis(
        time_step=1e-3, output_step=1e-2, n_freq=40, freq_spacing="log",
        freq_min=0.69, freq_max=83.0,  # wavelengths 1-120 m at 300 km/h; set for the speed below
        mode_max_frequency=100.0,
        channels=("bridge.span*.mid.*", "car*.body.acc_[yz]", "car1.bogie1.acc_[yz]", "car1.axle1.*force*"),
    )
    sc = Scenario(
        name="shinkansen_two_spans", speed_kmh=300.0, train=Train(vehicles=(car,) * cars),
        bridge=two_span_beam(), track=track, analysis=analysis,
        description=f"{cars} Shinkansen S300-like coaches over two 32 m spans, German low interference",
        source="examples/build_scenario_in_python.py",
    )
    if quick:
        sc = sc.replace(
            track=sc.track.replace(lead_in=40.0, run_out=5.0),
            analysis=sc.analysis.replace(n_freq=4, freq_min=1.0, freq_max=25.0, mode_max_frequency=40.0,
                                         time_step=2e-3, output_step=2e-2,
                                         contact_stiffness_z=5e8, contact_stiffness_y=5e8),
        )
    # the PEM band: the track's wavelengths at this speed (quick: at most 1-25 Hz), no higher than the
    # time step resolves; replace() validates again, so an impossible band is an error naming the key
    v, an = speed_kmh / 3.6, sc.analysis
    f_lo, f_hi = v / track.wavelength_max, min(v / track.wavelength_min, 0.1 / an.time_step)
    if quick:
        f_lo, f_hi = max(f_lo, 1.0), min(f_hi, 25.0)
    return sc.replace(speed_kmh=speed_kmh, analysis=an.replace(freq_min=f_lo, freq_max=f_hi))


def summary_table(result, k: float = 3.0) -> str:
    """Per channel: max |mean|, max sigma and max |mean| + k sigma over time."""
    rows = result.summary_rows(k)
    width = max(len(r[0]) for r in rows)
    lines = [f"{'channel':<{width}}  {'unit':<7}{'max|mean|':>12}{'max sigma':>12}{f'max|m|+{k:g}s':>12}"]
    lines += [f"{n:<{width}}  {u:<7}{m:>12.4e}{s:>12.4e}{p:>12.4e}" for n, u, m, s, p in rows]
    lines.append(f"(sigma over {result.band[0]:.3g}-{result.band[1]:.3g} Hz, {result.freq.size} frequencies)")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_common_arguments(parser, NAME)
    parser.add_argument("--speed", type=float, default=300.0, help="train speed [km/h] (default 300)")
    parser.add_argument("--cars", type=int, default=None, help="number of coaches (default 3; quick 1)")
    args = parser.parse_args(argv)
    if args.quick:  # the short approach of --quick is deliberate
        warnings.filterwarnings("ignore", message="track.lead_in", category=UserWarning)
    sc = build(args.speed, args.cars or (1 if args.quick else 3), args.quick)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tbx.save_scenario(sc, out / "scenario.toml")
    assert tbx.load_scenario(out / "scenario.toml") == sc  # the TOML round trip gives the same scenario

    t0 = time.perf_counter()
    det = tbx.run_deterministic(sc)
    det.save(out / "det")
    t_det = time.perf_counter() - t0
    print(summarize(det))
    print(f"deterministic run: {t_det:.1f} s\n")

    t0 = time.perf_counter()
    pem = run_study_pem(sc, out, args.workers, getattr(args, "engine", None), progress=not args.quick)
    t_pem = time.perf_counter() - t0
    print(f"{sc.name}: {sc.description}, {sc.speed_kmh:g} km/h; bridge: first axle on at "
          f"{sc.track.lead_in / sc.speed:.3g} s, first to last axle {sc.train.length:.4g} m")
    print(summary_table(pem))
    print(f"PEM: {pem.provenance['tasks']} tasks in {t_pem:.1f} s ({args.workers} workers, engine "
          f"{pem.provenance.get('engine')})")
    i = pem.index("bridge.span2.mid.acc_z")
    print(f"bridge.span2.mid.acc_z: max |mean| + 3 sigma = {np.max(np.abs(pem.mean[i]) + 3 * pem.std[i]):.3g} m/s^2")
    try:
        from tb_exudyn.plotting import plot_folder
        from tb_exudyn.report import write_report
    except ImportError:  # plotting is optional (matplotlib)
        print(f"results in {out.resolve()}")
        return 0
    channels = FIGURE_CHANNELS[:2] if args.quick else FIGURE_CHANNELS
    figures = plot_folder(out, channels=channels)
    report = write_report(out, channels=channels)
    print(f"results, {len(figures)} figures and {report.name} in {out.resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
