"""Lateral stability of the ICE cars with creep-guided wheelsets (issue 19): the least damped mode on
rigid track and the linear critical speed, with and without the yaw dampers, and the conicity's effect.

For each shipped creep car (``ice_motor_creep``, ``ice_trailer_creep``) the damped modes of the car on
rigid track (``tb_exudyn.builder.system_modes`` at t = 0: every axle on the approach) are computed at
a speed; the least damped mode is the one of smallest damping ratio among the vehicle and wheelset
modes in 0.2-60 Hz that an irregularity reaches (``ModeTable.reached``: the antisymmetric
longitudinal/spin wheelset modes, 37.8 Hz and creep-damped 4.4-4.6 %, which nothing excites, are
left out). The linear critical speed is the
lowest speed at which that damping ratio crosses zero: a scan from 100 to 500 km/h, then bisection.
The creep coefficients do not depend on speed; the creep damping falls as 1 / v.

    python examples/creep_car_stability.py [--quick] [--out DIR] [--speed 220]

Full setting: scan every 25 km/h, bisection to 0.5 km/h, conicities 0.05-0.40: about 10 s. ``--quick``:
the motor car only, scan every 100 km/h, bisection to 10 km/h, one conicity.
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

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.builder import build_model
from tb_exudyn.builder.system_modes import system_modes
from tb_exudyn.scenario import CreepCar, Train, load_vehicle

NAME = "creep_car_stability"
#: band of the modes considered [Hz]: above the weak springs' surge (0.09 Hz, no running mode), up to
#: the reference study's 60 Hz (above it the bogies' longitudinal modes against the wheelsets,
#: 63-72 Hz, which without yaw dampers keep only the wheels' common creep, 2.0-2.2 %: c_x = 0 in the data)
F_MIN, F_MAX = 0.2, 60.0


#: a mode is lateral when most of its kinetic energy lies in these components (out of the vertical plane)
LATERAL_COMPONENTS = ("lateral", "roll", "yaw")


def least_damped(car: CreepCar, speed_kmh: float, lateral: bool = False) -> tuple[float, float, str]:
    """(damping ratio, frequency [Hz], label) of the least damped reached vehicle mode of ``car``
    alone on rigid track at ``speed_kmh`` (``lateral``: among the lateral modes only)."""
    base = tbx.load_scenario("quick")
    sc = base.replace(speed_kmh=speed_kmh, train=Train(vehicles=(car,)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = system_modes(sc, model=build_model(sc, warn=False))
    veh = table.of_kind("vehicle", "contact")
    keep = (veh.frequency > F_MIN) & (veh.frequency <= F_MAX) & veh.reached() & np.isfinite(veh.damping_ratio)
    if lateral:
        out_of_plane = np.array([d.component in LATERAL_COMPONENTS for d in veh.dofs], dtype=float)
        keep &= veh.shares @ out_of_plane > 0.5
    veh = veh.select(keep)
    i = int(np.argmin(veh.damping_ratio))
    return float(veh.damping_ratio[i]), float(veh.frequency[i]), veh.label[i]


def critical_speed(car: CreepCar, step: float, tol: float, v_max: float = 500.0) -> float:
    """Lowest speed [km/h] in 100 ... v_max where the least damped mode's damping ratio is zero (nan:
    stable throughout): scan in ``step``, then bisection to ``tol``."""
    lo = 100.0
    if least_damped(car, lo)[0] <= 0.0:
        return float("nan")
    v = lo
    while v < v_max:
        hi = min(v + step, v_max)
        if least_damped(car, hi)[0] <= 0.0:
            lo = v
            while hi - lo > tol:
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if least_damped(car, mid)[0] > 0.0 else (lo, mid)
            return 0.5 * (lo + hi)
        v = hi
    return float("nan")


def with_conicity(car: CreepCar, conicity: float) -> CreepCar:
    """The car with another equivalent conicity (and contact-angle parameter = conicity: conical wheels)."""
    return car.replace(contact=car.contact.replace(conicity=conicity, contact_angle_parameter=conicity))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small smoke setting (seconds)")
    parser.add_argument("--out", default=str(Path("examples_out") / NAME), help=f"output folder (default ./examples_out/{NAME})")
    parser.add_argument("--speed", type=float, default=220.0, help="speed of the mode table [km/h] (default 220)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    names = ("ice_motor_creep",) if args.quick else ("ice_motor_creep", "ice_trailer_creep")
    step, tol = (100.0, 10.0) if args.quick else (25.0, 0.5)
    conicities = (0.15,) if args.quick else (0.05, 0.10, 0.15, 0.20, 0.30, 0.40)
    lines = [f"Least damped reached vehicle mode on rigid track at {args.speed:g} km/h and linear critical speed",
             f"{'car':<20}{'yaw dampers':<13}{'zeta':>8}{'f [Hz]':>9}{'v_crit [km/h]':>15}  mode"]
    for name in names:
        car = load_vehicle(name)
        for label, c in (("yes", car), ("no", car.replace(yaw_damper=None))):
            z, f, what = least_damped(c, args.speed)
            vc = critical_speed(c, step, tol)
            lines.append(f"{name:<20}{label:<13}{z:>8.4f}{f:>9.3f}{vc:>15.1f}  {what}")
            zl, fl, what_l = least_damped(c, args.speed, lateral=True)
            lines.append(f"{'':<20}{'':<13}{zl:>8.4f}{fl:>9.3f}{'':>15}  least damped lateral: {what_l}")
    lines += ["", f"Conicity (= contact-angle parameter), with yaw dampers, at {args.speed:g} km/h",
              f"{'car':<20}{'conicity':>9}{'zeta':>8}{'f [Hz]':>9}{'v_crit [km/h]':>15}  mode"]
    for name in names:
        car = load_vehicle(name)
        for lam in conicities:
            c = with_conicity(car, lam)
            z, f, what = least_damped(c, args.speed)
            vc = critical_speed(c, step, tol)
            lines.append(f"{name:<20}{lam:>9.2f}{z:>8.4f}{f:>9.3f}{vc:>15.1f}  {what}")
    lines.append(f"(critical speed: scan {100:g}-500 km/h every {step:g}, bisection to {tol:g} km/h; nan: none there; "
                 f"{time.perf_counter() - t0:.1f} s)")
    text = "\n".join(lines)
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "stability.txt").write_text(text + "\n", encoding="utf-8")
    print(f"stability.txt in {out.resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
