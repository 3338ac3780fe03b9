"""``result.plot``: the accessor of a result's figures (results.base.PlotAccessor), and matplotlib
loaded only when a figure is made.

The problem: the synthetic results of synthetic_results.py (no solver run). The figures are those of
the plotting functions the accessor names (same axes, same lines): compared by their line data,
which must be equal (the same arrays drawn, no tolerance). The import check runs in a fresh
interpreter, whose ``sys.modules`` says what was imported.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from tb_exudyn import plotting
from tb_exudyn.errors import SettingError

_spec = importlib.util.spec_from_file_location("synthetic_results", Path(__file__).with_name("synthetic_results.py"))
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)


def _lines(fig: Figure) -> list[np.ndarray]:
    return [np.asarray(line.get_ydata()) for ax in fig.axes for line in ax.get_lines()]


def test_the_accessor_draws_what_the_plotting_functions_draw():
    r, th = synthetic.pem_response(), synthetic.time_history()
    name = "car1.body.acc_y"
    pairs = [(r.plot.bounds(name, k=2.0), plotting.plot_bounds(r, name, k=2.0)),
             (r.plot.psd_slices(name), plotting.plot_psd_slices(r, name)),
             (th.plot.history([name, "car1.axle1.force_y"]), plotting.plot_time_history(th, [name, "car1.axle1.force_y"])),
             (r.plot(name), plotting.plot_bounds(r, name))]
    for got, want in pairs:
        assert isinstance(got, Figure)
        a, b = _lines(got), _lines(want)
        assert len(a) == len(b) and all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a, b))
    assert isinstance(r.plot.psd_map(name), Figure)
    with pytest.raises(KeyError, match="no channel"):
        th.plot.history(["car1.body.acc_y", "car9.body.acc_y"])
    with pytest.raises(SettingError, match="kind"):
        r.plot(name, "spectrogram")


def test_results_load_and_check_without_matplotlib(tmp_path):
    folder = synthetic.time_history().save(tmp_path / "th")
    code = ("import sys, tb_exudyn\n"
            f"r = tb_exudyn.load_results({str(folder)!r})\n"
            "r.checks(); r.arrays(); r.plot\n"
            "assert 'matplotlib' not in sys.modules, 'matplotlib loaded before a figure'\n"
            "r.plot.history(r.channel_names[0])\n"
            "assert 'matplotlib' in sys.modules\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          cwd=Path(__file__).resolve().parents[2])
    assert done.returncode == 0, done.stderr
