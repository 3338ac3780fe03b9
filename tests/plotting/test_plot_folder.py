"""plot_folder: figures of saved results, written atomically next to them."""

from __future__ import annotations

import pytest

from tb_exudyn.errors import ResultsError
from tb_exudyn.plotting import plot_folder, save_figure, plot_bounds


def _png(path):
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_folder_of_one_result(tmp_path, pem):
    pem.save(tmp_path / "pem")
    files = plot_folder(tmp_path / "pem", channels=["car1.body.acc_y"], formats=("png", "svg"))
    fig_dir = tmp_path / "pem" / "figures"
    names = sorted(p.name for p in files)
    assert names == sorted(f"car1.body.acc_y.{kind}.{fmt}" for kind in ("bounds", "psd_map", "psd_slices")
                           for fmt in ("png", "svg"))
    assert all(p.parent == fig_dir and p.stat().st_size > 1000 for p in files)
    assert all(_png(p) for p in files if p.suffix == ".png")
    assert "<svg" in (fig_dir / "car1.body.acc_y.bounds.svg").read_text()[:500]
    assert not list(fig_dir.glob(".*"))  # no temporary files left behind


def test_plot_folder_of_several_results_compares_pem_and_mc(tmp_path, pem, mc, th):
    pem.save(tmp_path / "pem")
    mc.save(tmp_path / "mc")
    th.save(tmp_path / "det")
    files = plot_folder(tmp_path, channels="car1.axle1.force_y")
    rel = sorted(str(p.relative_to(tmp_path)) for p in files)
    assert rel == [
        "det/figures/car1.axle1.force_y.history.png",
        "figures/car1.axle1.force_y.pem_vs_mc.png",
        "mc/figures/car1.axle1.force_y.bounds.png",  # Monte Carlo: no PSD map
        "pem/figures/car1.axle1.force_y.bounds.png",
        "pem/figures/car1.axle1.force_y.psd_map.png",
        "pem/figures/car1.axle1.force_y.psd_slices.png",
    ]
    assert all(_png(p) for p in files)


def test_plot_folder_errors(tmp_path, pem):
    with pytest.raises(ResultsError, match="no tb_exudyn result"):
        plot_folder(tmp_path)
    with pytest.raises(ValueError, match="cannot write figures as 'docx'"):
        save_figure(plot_bounds(pem, "car1.body.acc_y"), tmp_path / "x.docx")
    assert not list(tmp_path.iterdir())
