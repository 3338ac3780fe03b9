"""The reference study's 3-sigma envelopes (Li & Zhu, figures 6-8): mean +- 3 sigma against time.

Same scenario as ``li_zhu_2011_psd_maps.py`` (four ICE cars, three 32 m spans on piers, 220 km/h,
German low interference). The mean is the deterministic run (gravity, smooth track), sigma comes from
PEM; the band mean +- 3 sigma bounds the response (3-sigma rule for Gaussian irregularities) for

- figure 6: the bridge mid-span (middle span) displacement and acceleration, lateral and vertical,
  ``bridge.span2.mid.{disp,acc}_{y,z}``;
- figure 7: the car body of the first motor car, ``car1.body.{disp,acc}_{y,z}``;
- figure 8: the wheel-rail forces on its first wheelset, vertical ``car1.axle1.left.force_z``,
  ``car1.axle1.right.force_z`` and lateral ``car1.axle1.force_y``.

Prints per channel max |mean|, max sigma, max |mean| + 3 sigma, the ratio 3 max sigma / max |mean|,
and the share of the crossing during which the band spans zero (mean - 3 sigma < 0 <
mean + 3 sigma): the study's reading is a narrow band for the bridge displacement and the vertical wheel
force (the mean dominates) and a band across zero for the accelerations and the lateral wheel force
(the irregularity dominates). Also prints sigma of the first wheelset's lateral force and the leading
bogie's lateral acceleration at the crossing events, with the grid frequency holding most of the
final variance (see docs/findings.md on the lightly damped bogie lateral/yaw mode). Writes
``envelopes.csv``, ``envelopes.txt`` and ``figures/fig6-8.*.bounds.png``.

    python examples/li_zhu_2011_envelopes.py [--from DIR] [--quick] [--n-freq N] [--workers N] [--out DIR]

``--from DIR``: use the PEM result saved by ``li_zhu_2011_psd_maps.py --out DIR`` (``DIR/pem``) instead
of computing one. Without it the sweep runs here (PSD maps not kept): the study's 200 frequencies,
about 20 s with the batched engine on 2 cores, over an hour with ``--engine exudyn``; ``--n-freq 400``
converges the wheel-rail forces (docs/findings.md). ``--quick``: the PSD-map script's smoke setting.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the PSD-map script, imported below

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.plotting.data import crossing_times
from tb_exudyn.results import RandomResponse
from tb_exudyn.results.export import write_table_csv

from li_zhu_2011_psd_maps import (
    add_common_arguments,
    add_scenario_argument,
    quiet_quick_warnings,
    run_study_pem,
    study_scenario,
)

NAME = "li_zhu_2011_envelopes"

FIGURES = (
    ("6", "bridge.span2.mid.disp_y"), ("6", "bridge.span2.mid.disp_z"),
    ("6", "bridge.span2.mid.acc_y"), ("6", "bridge.span2.mid.acc_z"),
    ("7", "car1.body.disp_y"), ("7", "car1.body.disp_z"), ("7", "car1.body.acc_y"), ("7", "car1.body.acc_z"),
    ("8", "car1.axle1.left.force_z"), ("8", "car1.axle1.right.force_z"), ("8", "car1.axle1.force_y"),
)

#: channels whose sigma is printed at the crossing events (the bogie lateral/yaw mode)
GROWTH = ("car1.axle1.force_y", "car1.bogie1.acc_y", "car1.body.acc_y", "bridge.span2.mid.acc_y")


def load_pem(folder: Path) -> RandomResponse:
    """The PEM result in ``folder/pem`` (as the PSD-map script saves it) or in ``folder`` itself."""
    for path in (folder / "pem", folder):
        if (path / "meta.json").exists():
            result = tbx.load_results(path)
            if not isinstance(result, RandomResponse):
                raise SystemExit(f"{path}: not a random response")
            missing = [ch for _, ch in FIGURES if ch not in result.channels]
            if missing:
                raise SystemExit(f"{path}: the result lacks the channels {missing}; "
                                 "run li_zhu_2011_psd_maps.py (or this script without --from)")
            return result
    raise SystemExit(f"{folder}: no PEM result (expected {folder / 'pem' / 'meta.json'})")


def envelope_rows(pem: RandomResponse, k: float = 3.0) -> list[dict]:
    """Per figure channel: the numbers behind the envelope figures (see the module docstring).

    ``ratio``: k max sigma / max |mean| (both over the whole run): well below 1, the band is narrow
    around the mean; above 1, the random part dominates. ``zero_share``: share of the time while any
    axle is on the bridge during which mean - k sigma < 0 < mean + k sigma.
    """
    c = crossing_times(pem.scenario)
    on = (pem.time >= c.first_on) & (pem.time <= c.last_off)
    lo, hi = pem.bounds(k)
    rows = []
    for fig, ch in FIGURES:
        i = pem.index(ch)
        m, s = pem.mean[i], pem.std[i]
        j = int(np.argmax(s))
        spans_zero = (lo[i] < 0) & (hi[i] > 0)
        max_mean = float(np.max(np.abs(m)))
        rows.append({
            "figure": fig, "channel": ch, "unit": pem.unit(ch),
            "max_abs_mean": max_mean, "max_sigma": float(s[j]), "t_max_sigma": float(pem.time[j]),
            "max_abs_mean_plus_3sigma": float(np.max(np.abs(m) + k * s)),
            "ratio_3sigma_to_mean": float(k * s[j] / max_mean) if max_mean > 0 else float("inf"),
            "zero_share_on_bridge": float(spans_zero[on].mean()) if on.any() else float("nan"),
        })
    return rows


def rows_table(rows: list[dict], pem: RandomResponse) -> str:
    head = (f"{'fig':<4}{'channel':<26}{'unit':<7}{'max|mean|':>11}{'max sigma':>11}{'at t [s]':>9}"
            f"{'max|m|+3s':>11}{'3s/|m|':>9}{'spans 0':>9}")
    lines = [head]
    for r in rows:
        lines.append(f"{r['figure']:<4}{r['channel']:<26}{r['unit']:<7}{r['max_abs_mean']:>11.4g}"
                     f"{r['max_sigma']:>11.4g}{r['t_max_sigma']:>9.3g}{r['max_abs_mean_plus_3sigma']:>11.4g}"
                     f"{r['ratio_3sigma_to_mean']:>9.3g}{r['zero_share_on_bridge']:>9.0%}")
    lines.append(f"(3s/|m|: 3 max sigma / max |mean| over the run; spans 0: share of the crossing (first axle on "
                 f"to last axle off) with mean - 3 sigma < 0 < mean + 3 sigma; sigma over "
                 f"{pem.band[0]:.3g}-{pem.band[1]:.3g} Hz, {pem.freq.size} frequencies)")
    return "\n".join(lines)


def growth_table(pem: RandomResponse) -> str:
    """sigma of the GROWTH channels at the crossing events and at the end of the run, and (with a PSD
    map) the grid frequency holding most of sigma^2 at the end, with its share."""
    c = crossing_times(pem.scenario)
    events = sorted([("first on", c.first_on), ("first off", c.first_off), ("last on", c.last_on),
                     ("last off", c.last_off), ("end", float(pem.time[-1]))], key=lambda e: e[1])
    width = max(len(ch) for ch in GROWTH) + 2
    lines = [f"{'sigma at':<{width}}{'unit':<7}" + "".join(f"{name + f' {t:.2f}s':>17}" for name, t in events)
             + ("   largest cell at the end" if pem.psd is not None else "")]
    for ch in GROWTH:
        if ch not in pem.channels:
            continue
        i = pem.index(ch)
        vals = [pem.std[i, int(np.argmin(np.abs(pem.time - t)))] for _, t in events]
        line = f"{ch:<{width}}{pem.unit(ch):<7}" + "".join(f"{v:>17.4g}" for v in vals)
        row = pem.psd_row(ch) if pem.psd is not None else None
        if row is not None:
            var = pem.psd[row, :, -1] * pem.df
            kk = int(np.argmax(var))
            rest = math.sqrt(max(var.sum() - var[kk], 0.0))
            line += (f"   {pem.freq[kk]:.3g} Hz: {var[kk] / var.sum():.1%} of sigma^2 "
                     f"(sigma without it {rest:.4g})" if var.sum() > 0 else "")
        lines.append(line)
    return "\n".join(lines)


def save_figures(pem: RandomResponse, folder: Path) -> list[Path]:
    from tb_exudyn.plotting import plot_bounds, save_figure

    return [save_figure(plot_bounds(pem, ch, k=3.0), folder / f"fig{fig}.{ch}.bounds.png") for fig, ch in FIGURES]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_common_arguments(parser, NAME)
    add_scenario_argument(parser)
    parser.add_argument("--from", dest="source", default=None,
                        help="folder of a saved PEM result (li_zhu_2011_psd_maps.py --out DIR): no sweep")
    parser.add_argument("--n-freq", type=int, default=None,
                        help="number of PEM frequencies over 0.3-60 Hz (default: the study's 200)")
    parser.add_argument("--spacing", choices=("linear", "log"), default=None,
                        help="spacing of the frequency grid (default: the study's linear)")
    args = parser.parse_args(argv)
    out = Path(args.out)
    t0 = time.perf_counter()
    if args.source:
        pem = load_pem(Path(args.source))
        origin = f"loaded from {Path(args.source).resolve()}"
    else:
        if args.quick:
            quiet_quick_warnings()
        sc = study_scenario(args.quick, args.n_freq, args.spacing, name=args.scenario)
        pem = run_study_pem(sc, out, args.workers, getattr(args, "engine", None), progress=not args.quick,
                            keep_psd=False)
        origin = f"computed in {time.perf_counter() - t0:.1f} s ({args.workers} workers)"
    sc = pem.scenario
    rows = envelope_rows(pem)
    text = (f"{sc.name}: {len(sc.train.vehicles)} cars at {sc.speed_kmh:g} km/h; PEM {pem.freq.size} frequencies "
            f"{pem.band[0]:.3g}-{pem.band[1]:.3g} Hz, engine {pem.provenance.get('engine')}, {origin}\n\n"
            + rows_table(rows, pem) + "\n\n" + growth_table(pem))
    print(text)
    out.mkdir(parents=True, exist_ok=True)
    (out / "envelopes.txt").write_text(text + "\n", encoding="utf-8")
    write_table_csv(rows, out / "envelopes.csv")
    try:
        paths = save_figures(pem, out / "figures")
    except ImportError:  # plotting is optional (matplotlib)
        paths = []
    print(f"envelopes.csv, envelopes.txt and {len(paths)} figures in {out.resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
