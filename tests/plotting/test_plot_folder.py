"""plot_folder: figures of saved results, drawn in parallel, written atomically inside the folder given."""

from __future__ import annotations

import json

import pytest

from tb_exudyn.errors import ResultsError
from tb_exudyn.plotting import plot_bounds, plot_folder, save_figure
from tb_exudyn.report import write_report


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


def test_default_figures_are_drawn_in_parallel_and_match_the_serial_ones(tmp_path, pem):
    """12 figures (4 channels x bounds, PSD map, PSD slices): 2 drawing processes (this one and a
    spawned worker) write byte-identical PNG files to one process."""
    for w in (1, 2):
        pem.save(tmp_path / f"w{w}")
    serial = plot_folder(tmp_path / "w1", workers=1)
    parallel = plot_folder(tmp_path / "w2", workers=2, progress=True)
    assert len(serial) == 12 and [p.name for p in parallel] == [p.name for p in serial]
    assert all(a.read_bytes() == b.read_bytes() for a, b in zip(serial, parallel))


def _hostile(tmp_path, pem, channel):
    """A result folder whose meta.json names a channel as given."""
    pem.save(tmp_path / "out" / "pem")
    meta_path = tmp_path / "out" / "pem" / "meta.json"
    meta = json.loads(meta_path.read_text())
    meta["channels"][1] = channel
    meta_path.write_text(json.dumps(meta))
    return meta_path


def test_a_channel_name_cannot_write_outside_the_folder(tmp_path, pem):
    meta = _hostile(tmp_path, pem, "car1/../../../escaped")
    with pytest.raises(ResultsError) as err:
        plot_folder(tmp_path / "out", channels="*")
    message = str(err.value)
    assert str(meta) in message and "\n" not in message and "escaped" in message
    assert not list(tmp_path.rglob("*.png")) and not (tmp_path / "escaped.bounds.png").exists()
    with pytest.raises(ResultsError, match="escaped"):
        write_report(tmp_path / "out", channels="*")
    assert not (tmp_path / "out" / "report.html").exists()


def test_a_symlinked_figures_folder_is_refused(tmp_path, pem):
    pem.save(tmp_path / "out" / "pem")
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (tmp_path / "out" / "pem" / "figures").symlink_to(outside)
    with pytest.raises(ResultsError) as err:
        plot_folder(tmp_path / "out")
    assert str(tmp_path / "out" / "pem" / "figures") in str(err.value) and "symbolic link" in str(err.value)
    assert not list(outside.iterdir())


def test_a_symlinked_result_folder_cannot_lead_outside(tmp_path, pem):
    outside = tmp_path / "elsewhere"
    pem.save(outside)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "pem").symlink_to(outside)
    with pytest.raises(ResultsError, match="symbolic link"):
        plot_folder(tmp_path / "out")
    assert not (outside / "figures").exists()


def test_a_pages_figure_is_drawn_once_with_savefigs_pixels(pem):
    """figure_pngs draws a figure once on Agg and encodes both PNGs from its pixels in memory (the
    page's palette copy no longer decodes the file). Reference: matplotlib's own
    ``savefig(format="png")`` of the same figure, and compact_png of those bytes (the page's copy as
    it was made before). Exact: the same Agg drawing gives the same pixels, and the palette copy is
    the same median cut of the same RGB pixels; only the file's zlib level and colour type (RGB
    when opaque) may differ."""
    import io

    import numpy as np
    from PIL import Image

    from tb_exudyn.plotting import plot_psd_map
    from tb_exudyn.plotting.files import compact_png, figure_pngs

    for make in (lambda: plot_bounds(pem, "car1.body.acc_y"), lambda: plot_psd_map(pem, "car1.body.acc_y")):
        png, page = figure_pngs(make())
        buf = io.BytesIO()
        make().savefig(buf, format="png", dpi=100)

        def pixels(data, mode):
            with Image.open(io.BytesIO(data)) as im:
                return np.asarray(im.convert(mode))

        assert np.array_equal(pixels(png, "RGBA"), pixels(buf.getvalue(), "RGBA"))
        assert np.array_equal(pixels(page, "RGB"), pixels(compact_png(buf.getvalue()), "RGB"))
        assert len(page) < len(png) / 2  # the page's copy is the small one


def test_a_page_drawn_on_a_pool_started_ahead_shows_every_figure_it_drew(tmp_path, pem):
    """``tb-exudyn run``'s path (issue 49): figure processes started before the analysis
    (execution.standby), given the figures of the channels known without the checks first, then the
    page. Every figure file drawn is embedded once, no figure is drawn that the page does not show,
    and the page's pictures are the bytes of the page drawn in one process (the same drawing:
    the reference is write_report without a pool)."""
    import re

    from tb_exudyn.cli.run import FIGURE_MODULES
    from tb_exudyn.execution.standby import standby_pool
    from tb_exudyn.plotting.data import pattern_channels
    from tb_exudyn.plotting.files import PageDrawing, figure_jobs

    for name in ("pool", "serial"):
        pem.save(tmp_path / name / "pem")
    out = tmp_path / "pool"
    with standby_pool(1, FIGURE_MODULES) as pool:
        drawing = PageDrawing(pool)
        early = figure_jobs(out, [(out / "pem", pem)], pattern_channels(pem))
        drawing.submit(early)
        drawing.submit(early)  # a job is drawn once
        write_report(out, drawing=drawing)
    write_report(tmp_path / "serial", workers=1)
    pages = [re.findall(r'src="data:image/png;base64,([^"]+)"', (tmp_path / n / "report.html").read_text())
             for n in ("pool", "serial")]
    files = sorted((out / "pem" / "figures").glob("*.png"))
    assert 0 < len(early) <= len(files) == len(pages[0]) == len(set(pages[0]))
    assert pages[0] == pages[1]
