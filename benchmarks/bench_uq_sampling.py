"""Benchmark: polynomial chaos against plain sampling of the same PEM (issue 46; docs/uq.md, "PCE against
sampling").

    python benchmarks/bench_uq_sampling.py [--scenario quick] [--order 3] [--points 256] [--workers 2]
                                           [--boot 2000] [--out DIR]

The three uncertain keys of ``bench_uq.py`` (girder E lognormal cov 5 %, damping +-30 %, girder mass
+-5 %). Two studies of the same PEM (``tbx.run_uq``, the batched engine):

- the expansion: order ``--order`` on the tensor Gauss grid ((order + 1)^3 nodes);
- plain sampling: ``--points`` low-discrepancy points (chaospy's Sobol sequence of the keys' germs, the
  study's ``sobol`` design, whose nodes are those points): each point one PEM.

Per channel, max sigma over the crossing: its mean and its 2.5 and 97.5 % points (the 95 % band) over
the keys, from the expansion (its mean; its quantiles read off the surrogate at 2^16 Sobol points) and
from the sample (the sample mean; the empirical quantiles), the sample's standard error by bootstrap
(``--boot`` resamples of the points with replacement; for low-discrepancy points an upper estimate, as
they are more even than random ones), and the difference in standard errors. Then the surrogate
evaluated at the very sample points against the PEM there (the RMS and largest relative error): a
check that does not depend on the sampling error. The sampling study is run first, under its own
folder, so that an interrupted run resumes (``--resume``).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout: the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_uq import KEYS, cpu_seconds  # noqa: E402

#: the quantiles of the 95 % band [%]
BAND = (2.5, 97.5)
#: the PEM's own resolution of max sigma, relative (below it a difference is not the surrogate's: the
#: adaptive grid moves with the keys' modes; the axle forces of ``quick`` move by 2e-6 over the keys)
RESOLUTION = 1e-4
#: the surrogate's samples for its quantiles (a Sobol design of the germs)
SURROGATE_SAMPLES = 2**16


def study(scenario: str, design: str, order: int, nodes: int | None, workers: int, out: Path, resume: bool):
    import tb_exudyn as tbx

    c0, t0 = cpu_seconds(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = tbx.run_uq(scenario, KEYS, order=order, design=design, nodes=nodes, workers=workers, progress=False,
                       out=out, overwrite=not resume, resume=resume, keep_checkpoint=False)
    c1 = cpu_seconds()
    print(f"{design} study: {r.provenance['n_nodes']} nodes, wall {time.perf_counter() - t0:.1f} s, CPU "
          f"{c1[0] - c0[0] + c1[1] - c0[1]:.1f} s, load average {os.getloadavg()[0]:.2f}")
    return r


def surrogate(result, keys, order: int):  # noqa: ANN001, ANN201
    """The expansion of every quantity refitted from the result's nodes (the functions the study uses),
    as (germs, expansion)."""
    from tb_exudyn.methods.uq import pce

    germs = [pce.key_germ(k) for k in keys]
    x = np.stack([pce.key_germ_value(k, result.data["node_values"][:, j]) for j, k in enumerate(keys)])
    w = result.data["node_weights"]
    return germs, pce.fit(germs, order, x, None if np.isnan(w).all() else w, result.data["node_quantities"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", default="quick")
    parser.add_argument("--order", type=int, default=3)
    parser.add_argument("--points", type=int, default=256)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--boot", type=int, default=2000)
    parser.add_argument("--out", default="/tmp/bench_uq_sampling")
    parser.add_argument("--resume", action="store_true")
    parser.add_argument("--saved", action="store_true", help="read the two studies saved in --out instead of running them")
    a = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import chaospy

    import tb_exudyn as tbx
    from tb_exudyn.methods.uq import pce
    from tb_exudyn.scenario.uncertain import check_uncertain

    keys = check_uncertain(tbx.load_scenario(a.scenario), KEYS, "bench_uq_sampling")
    if a.saved:
        from tb_exudyn.results.uq import load_uq

        sampled, pce_study = load_uq(Path(a.out) / "sampling" / "uq"), load_uq(Path(a.out) / "pce" / "uq")
    else:
        sampled = study(a.scenario, "sobol", a.order, a.points, a.workers, Path(a.out) / "sampling", a.resume)
        pce_study = study(a.scenario, "tensor", a.order, None, a.workers, Path(a.out) / "pce", a.resume)
    germs, e = surrogate(pce_study, keys, a.order)
    xs = np.asarray(chaospy.J(*germs).sample(SURROGATE_SAMPLES, rule="sobol"), dtype=float).reshape(len(germs), -1)
    on_surrogate = e(pce.basis(germs, a.order, xs)[1])
    x_pts = np.stack([pce.key_germ_value(k, sampled.data["node_values"][:, j]) for j, k in enumerate(keys)])
    at_points = e(pce.basis(germs, a.order, x_pts)[1])
    y = np.asarray(sampled.data["node_quantities"], dtype=float)
    rng = np.random.default_rng(46)
    idx = rng.integers(0, y.shape[0], size=(a.boot, y.shape[0]))
    print(f"max sigma over the crossing, {a.scenario}: the expansion (order {a.order}, {pce_study.provenance['n_nodes']} "
          f"nodes) against {y.shape[0]} Sobol points of the same PEM. Mean: the sample's bootstrap standard error "
          f"({a.boot} resamples) and d, the difference in standard errors. 2.5 and 97.5 % points: the sample's "
          "distribution-free 95 % interval (order statistics) and whether the expansion's point is inside. Last: the "
          "surrogate at the sample's points against the PEM there (RMS / largest relative error)")
    print(f"{'channel':<34} {'mean PCE':>10} {'sample':>10} {'(se)':>9} {'d':>6}  "
          f"{'2.5 % PCE':>10} {'sample':>10} {'interval':>21}  {'97.5 % PCE':>10} {'sample':>10} {'interval':>21}  pointwise")
    n, counts = y.shape[0], {"mean": [0, 0], "band": [0, 0]}
    for j, name in enumerate(pce_study.quantities):
        col = y[:, j]
        if not name.startswith("max_sigma:") or not np.all(np.isfinite(col)) or np.ptp(col) == 0:
            continue
        resolved = np.ptp(col) > RESOLUTION * abs(col.mean())  # the keys move it more than the PEM resolves
        se = col[idx].mean(axis=1).std(ddof=1)
        d = (e.mean[j] - col.mean()) / se
        ok_mean = abs(d) <= 3 or abs(e.mean[j] - col.mean()) <= RESOLUTION * abs(col.mean())
        cells = [f"{e.mean[j]:10.4g} {col.mean():10.4g} ({se:7.2g}) {d:+6.2f}"]
        ok_band = True
        for p_, q_pce in zip(BAND, np.percentile(on_surrogate[:, j], BAND)):
            lo, hi = order_interval(col, p_ / 100)
            inside = lo - RESOLUTION * abs(lo) <= q_pce <= hi + RESOLUTION * abs(hi)
            ok_band &= bool(inside)
            cells.append(f"{q_pce:10.4g} {np.percentile(col, p_):10.4g} [{lo:9.4g}, {hi:9.4g}]{' ' if inside else '*'}")
        for k, ok in (("mean", ok_mean), ("band", ok_band)):
            counts[k][0] += ok
            counts[k][1] += 1
        rel = (at_points[:, j] - col) / np.abs(col)
        print(f"{name.split(':', 1)[1]:<34} " + "  ".join(cells)
              + f"  {np.sqrt(np.mean(rel ** 2)):.1e} / {np.abs(rel).max():.1e}{'' if resolved else ' (hardly moved)'}")
    print(f"means within 3 standard errors (or {RESOLUTION:g} of the mean): {counts['mean'][0]} of {counts['mean'][1]}; "
          f"both band points inside the sample's 95 % intervals: {counts['band'][0]} of {counts['band'][1]} (* outside)")


def order_interval(col: np.ndarray, p: float) -> tuple[float, float]:
    """The distribution-free 95 % interval of the p-quantile from the sorted sample: the order statistics
    of ranks n p -+ 1.96 sqrt(n p (1 - p)) (the binomial count of points below the quantile)."""
    x, n = np.sort(col), col.size
    half = 1.96 * np.sqrt(n * p * (1 - p))
    lo, hi = int(np.floor(n * p - half)), int(np.ceil(n * p + half))
    return float(x[max(lo, 1) - 1]), float(x[min(hi, n) - 1])


if __name__ == "__main__":
    main()
