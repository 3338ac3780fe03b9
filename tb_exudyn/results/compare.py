"""PEM against Monte Carlo, channel by channel.

PEM gives the exact sigma(t) of the discretised spectrum (for a linear system); Monte Carlo with N
samples estimates it with a relative standard error of about 1/sqrt(2N) (for a Gaussian response;
a random-phase harmonic sum has lighter tails, so its error is smaller still). Per channel:

- the ratio sigma_MC(t) / sigma_PEM(t) and the fraction of compared times where it lies in the band
  1 +- k / sqrt(2N) that the sample size explains;
- the mean difference in units of its standard error, z(t) = (mean_MC - mean_PEM) / (s_MC / sqrt(N))
  (PEM's mean is the deterministic run, the exact mean of a linear system), and the fraction of
  compared times with |z| <= k.

Compared times: t >= t_min where sigma_PEM exceeds a fraction ``threshold`` of its maximum over
t >= t_min (ratios of tiny sigmas say nothing). Default t_min: 0 when the track tapers the
irregularity in (``track.taper_length`` > 0: every run starts in equilibrium with zero input, so PEM
and Monte Carlo analyse the same process from t = 0); without a taper, the time the first axle
reaches the bridge, because before it the start-up transients differ by design (PEM's runs start
at rest under the full harmonic input, Monte Carlo's from static equilibrium on the sampled track).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import ComparisonError
from .folders import load_results
from .random_response import RandomResponse




@dataclass(frozen=True)
class ChannelComparison:
    """One channel: sigma ratio MC/PEM and mean difference over the compared times."""

    channel: str
    unit: str
    n_times: int  #: compared time points
    sigma_pem_max: float
    ratio_median: float
    ratio_min: float
    ratio_max: float
    inside: float  #: fraction of compared times with |ratio - 1| <= k / sqrt(2N)
    mean_z_max: float  #: max |mean_MC - mean_PEM| / standard error
    mean_inside: float  #: fraction of compared times with |z| <= k


@dataclass(frozen=True)
class Comparison:
    """PEM against one Monte Carlo run; ``table()`` prints it."""

    n_samples: int
    k: float
    t_min: float
    threshold: float
    pem_band: tuple[float, float]
    mc_band: tuple[float, float]
    rows: tuple[ChannelComparison, ...]

    @property
    def band(self) -> tuple[float, float]:
        """The band 1 +- k / sqrt(2N) of the sigma ratio."""
        h = self.k / math.sqrt(2 * self.n_samples)
        return 1.0 - h, 1.0 + h

    def row(self, channel: str) -> ChannelComparison:
        for r in self.rows:
            if r.channel == channel:
                return r
        raise KeyError(f"channel {channel!r} not compared; compared: {[r.channel for r in self.rows]}")

    def summary(self) -> str:
        """One line first: how many channels have their median sigma ratio in the band, and the worst
        channel (the largest |median ratio - 1|, then the smallest share of times inside)."""
        lo, hi = self.band
        if not self.rows:
            return "no channel compared"
        ok = sum(lo <= r.ratio_median <= hi for r in self.rows)
        worst = max(self.rows, key=lambda r: (abs(r.ratio_median - 1.0), -r.inside))
        return (f"{ok} of {len(self.rows)} channels with the median sigma ratio in [{lo:.3f}, {hi:.3f}]; worst "
                f"{worst.channel}: median {worst.ratio_median:.3f}, {100 * worst.inside:.0f} % of the times inside, "
                f"max |z| of the mean {worst.mean_z_max:.2f}")

    def table(self) -> str:
        lo, hi = self.band
        k = f"{self.k:g}"
        lines = [
            self.summary(),
            f"PEM against Monte Carlo (N = {self.n_samples}): sigma ratio MC/PEM expected in 1 +- {k}/sqrt(2N) "
            f"= [{lo:.3f}, {hi:.3f}]; mean difference in standard errors z, expected |z| <= {k}",
            f"compared: t >= {self.t_min:.3g} s where sigma_PEM > {100 * self.threshold:g} % of its maximum; "
            f"band PEM {self.pem_band[0]:.4g}-{self.pem_band[1]:.4g} Hz, MC {self.mc_band[0]:.4g}-"
            f"{self.mc_band[1]:.4g} Hz" + ("" if np.allclose(self.pem_band, self.mc_band) else " (DIFFERENT bands)"),
        ]
        w = max([len("channel")] + [len(r.channel) for r in self.rows])
        head = (f"{'channel':<{w}}  {'unit':<7} {'max sigma PEM':>13}  {'ratio median [min, max]':<25} "
                f"{'inside band':>11}  {'max |z|':>7}  {f'|z|<={k}':>7}")
        lines += [head, "-" * len(head)]
        for r in self.rows:
            spread = f"{r.ratio_median:.3f} [{r.ratio_min:.3f}, {r.ratio_max:.3f}]"
            lines.append(f"{r.channel:<{w}}  {r.unit:<7} {r.sigma_pem_max:>13.4e}  {spread:<25} "
                         f"{100 * r.inside:>10.1f}%  {r.mean_z_max:>7.2f}  {100 * r.mean_inside:>6.1f}%")
        return "\n".join(lines)


def compare(pem: RandomResponse, mc: RandomResponse, channels: str | Sequence[str] | None = None, *,
            k: float = 3.0, threshold: float = 0.05, t_min: float | None = None) -> Comparison:
    """Compare a PEM result with a Monte Carlo result channel by channel.

    Parameters
    ----------
    pem, mc : the two random responses (same scenario and output times)
    channels : names or glob patterns (default: every channel both hold)
    k : band half-width in standard errors (ratio band 1 +- k / sqrt(2N), mean band |z| <= k)
    threshold : compare only where sigma_PEM > threshold * its maximum over t >= t_min
    t_min : first compared time [s]; default 0 with a taper, else lead_in / speed (see the module docstring)

    Raises
    ------
    ComparisonError (a ValueError) if the methods, output times or channels do not fit.
    """
    if not pem.kind.gaussian or not mc.kind.sampled:
        raise ComparisonError(f"compare needs a PEM and a Monte Carlo result, got {pem.method!r} and {mc.method!r}")
    if mc.n_samples < 2:
        raise ComparisonError(f"the Monte Carlo result has {mc.n_samples} samples; at least 2 are needed")
    if pem.time.shape != mc.time.shape or not np.allclose(pem.time, mc.time, rtol=0, atol=1e-9):
        raise ComparisonError(f"output times differ: PEM {pem.time.size} points to {pem.time[-1]:g} s, "
                         f"Monte Carlo {mc.time.size} points to {mc.time[-1]:g} s")
    names = pem.select(channels if channels is not None else "*")
    names = [c for c in names if c in mc.channels]
    if not names:
        raise ComparisonError(f"no channel of {channels!r} in both results")
    if t_min is None:
        track = pem.scenario.track
        t_min = 0.0 if getattr(track, "taper_length", 0.0) > 0 else track.lead_in / pem.scenario.speed
    window = pem.time >= t_min - 1e-12
    half = k / math.sqrt(2 * mc.n_samples)
    rows = []
    for c in names:
        s_pem, s_mc = pem.std[pem.index(c)], mc.std[mc.index(c)]
        peak = float(s_pem[window].max()) if window.any() else 0.0
        use = window & (s_pem > threshold * peak) & (peak > 0)
        if not use.any():
            nan = math.nan
            rows.append(ChannelComparison(c, pem.unit(c), 0, peak, nan, nan, nan, nan, nan, nan))
            continue
        ratio = s_mc[use] / s_pem[use]
        se = s_mc[use] / math.sqrt(mc.n_samples)
        diff = mc.mean[mc.index(c)][use] - pem.mean[pem.index(c)][use]
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(se > 0, np.abs(diff) / se, np.where(diff == 0, 0.0, np.inf))
        rows.append(ChannelComparison(
            channel=c, unit=pem.unit(c), n_times=int(use.sum()), sigma_pem_max=peak,
            ratio_median=float(np.median(ratio)), ratio_min=float(ratio.min()), ratio_max=float(ratio.max()),
            inside=float(np.mean(np.abs(ratio - 1.0) <= half)), mean_z_max=float(z.max()),
            mean_inside=float(np.mean(z <= k)),
        ))
    return Comparison(n_samples=mc.n_samples, k=k, t_min=float(t_min), threshold=threshold,
                      pem_band=tuple(pem.band), mc_band=tuple(mc.band), rows=tuple(rows))  # type: ignore[arg-type]


def _result_folder(folder: str | Path, *subs: str) -> Path:
    """A result folder itself, or an ``--out`` folder holding it as the first of ``subs`` present."""
    folder = Path(folder)
    if not (folder / "meta.json").exists():
        for sub in subs:
            if (folder / sub / "meta.json").exists():
                return folder / sub
    return folder


def compare_folders(pem_dir: str | Path, mc_dir: str | Path, channels: str | Sequence[str] | None = None, *,
                    k: float = 3.0, threshold: float = 0.05, t_min: float | None = None) -> str:
    """The comparison table of saved results (for ``tb-exudyn compare PEM_DIR MC_DIR``).

    Each folder is a saved result or an ``--out`` folder holding ``pem/`` resp. ``mc/`` (the Exudyn
    Monte Carlo) or, without it, ``mc_linear/`` (the linear model's).
    """
    pem = load_results(_result_folder(pem_dir, "pem"))
    mc = load_results(_result_folder(mc_dir, "mc", "mc_linear"))
    if not isinstance(pem, RandomResponse) or not isinstance(mc, RandomResponse):
        raise ComparisonError(f"{pem_dir} and {mc_dir} must hold random responses (PEM and Monte Carlo results)")
    return compare(pem, mc, channels, k=k, threshold=threshold, t_min=t_min).table()
