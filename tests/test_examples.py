"""Every script in examples/ runs with ``--quick --out DIR`` and writes what it promises.

The scripts are found by globbing ``examples/*.py`` (files starting with ``_`` are helpers, not
scripts), so a new example is tested as soon as it exists. Each runs as a subprocess, as a user would
run it; EXPECTED lists the files a script must write (glob patterns relative to its --out folder);
a script not listed there must at least exit 0 and write something.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("exudyn")
pytestmark = [pytest.mark.exudyn, pytest.mark.slow]

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.glob("*.py") if not p.name.startswith("_"))

#: per script: files (glob patterns, relative to --out) that --quick must write
EXPECTED: dict[str, tuple[str, ...]] = {
    "build_scenario_in_python.py": (
        "scenario.toml", "det/meta.json", "det/arrays.npz", "pem/meta.json", "pem/arrays.npz", "report.html",
        "pem/figures/*.bounds.png", "pem/figures/*.psd_map.png",
    ),
    "li_zhu_2011_psd_maps.py": (
        "pem/meta.json", "pem/arrays.npz", "psd_peaks.txt",
        *(f"figures/fig{f}.{ch}.psd_{kind}.png"
          for f, ch in (("3a", "bridge.span2.mid.disp_y"), ("3b", "bridge.span2.mid.acc_y"),
                        ("4a", "car1.body.disp_y"), ("4b", "car1.body.acc_y"),
                        ("5a", "car1.bogie1.disp_y"), ("5b", "car1.bogie1.acc_y"))
          for kind in ("map", "slices")),
    ),
    "li_zhu_2011_envelopes.py": (
        "pem/meta.json", "envelopes.csv", "envelopes.txt",
        "figures/fig6.bridge.span2.mid.disp_y.bounds.png", "figures/fig6.bridge.span2.mid.acc_y.bounds.png",
        "figures/fig7.car1.body.acc_y.bounds.png", "figures/fig8.car1.axle1.force_y.bounds.png",
        "figures/fig8.car1.axle1.left.force_z.bounds.png",
    ),
    "speed_sweep.py": ("speed_sweep.csv", "speed_sweep.png", "speed_sweep.html", "220/pem/meta.json",
                       "350/pem/meta.json"),
    "li_zhu_2011_verification.py": ("comparison.txt", "pem/meta.json", "mc/meta.json", "figures/*.pem_vs_mc.png"),
    "creep_car_stability.py": ("stability.txt",),
    "uq_reference_bridge.py": ("uq/meta.json", "uq/arrays.npz", "uq.txt"),
    "imported_modal_bridge.py": ("bridge/bridge.toml", "bridge/modes.csv", "bridge/shapes.csv", "scenario.toml",
                                 "comparison.txt", "alpha_1/det/meta.json"),
}

#: a --quick run must stay well under a minute on 2 free cores; this bound only catches a setting
#: that has grown by an order of magnitude on a shared, loaded machine
TIMEOUT = 300


def run_script(script: Path, *args: str) -> tuple[subprocess.CompletedProcess, float]:
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONWARNINGS": "ignore::DeprecationWarning"}
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True, timeout=TIMEOUT,
                          env=env, cwd=script.parent)
    return proc, time.perf_counter() - t0


def check_ran(proc: subprocess.CompletedProcess, script: Path) -> None:
    assert proc.returncode == 0, (f"{script.name} exited with {proc.returncode}\n--- stdout\n{proc.stdout[-3000:]}"
                                  f"\n--- stderr\n{proc.stderr[-3000:]}")


def test_examples_found():
    """The glob sees the scripts (a renamed folder would otherwise test nothing)."""
    names = {p.name for p in SCRIPTS}
    assert {"build_scenario_in_python.py", "li_zhu_2011_psd_maps.py", "li_zhu_2011_envelopes.py",
            "speed_sweep.py"} <= names


@pytest.fixture(scope="module")
def psd_maps_run(tmp_path_factory) -> tuple[subprocess.CompletedProcess, float, Path]:
    """The PSD-map script's quick run, shared with the envelope test that reads its result."""
    out = tmp_path_factory.mktemp("psd_maps") / "out"
    proc, seconds = run_script(EXAMPLES / "li_zhu_2011_psd_maps.py", "--quick", "--out", str(out))
    return proc, seconds, out


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_example_quick(script: Path, tmp_path: Path, request):
    if script.name == "li_zhu_2011_psd_maps.py":
        proc, seconds, out = request.getfixturevalue("psd_maps_run")
    else:
        out = tmp_path / "out"
        proc, seconds = run_script(script, "--quick", "--out", str(out))
    check_ran(proc, script)
    missing = [pat for pat in EXPECTED.get(script.name, ()) if not any(out.glob(pat))]
    wrote = sorted(str(p.relative_to(out)) for p in out.rglob("*"))[:40]
    assert not missing, f"{script.name} --quick did not write {missing}; it wrote {wrote}"
    assert out.is_dir() and any(out.iterdir()), f"{script.name} wrote nothing into {out}"
    assert str(out) in proc.stdout or str(out.resolve()) in proc.stdout, f"{script.name} does not say where it wrote"
    for check in NUMBERS.get(script.name, ()):
        check(out)
    print(f"{script.name} --quick: {seconds:.1f} s")


# ------------------------------------------------------------------ numbers the examples must give
def _static_axle_load(out: Path) -> None:
    """build_scenario_in_python: the deterministic run starts in static equilibrium on the rigid
    approach, so at t = 0 the first axle's two vertical wheel forces carry the static axle load of
    the symmetric car, g (m_body / 4 + m_bogie / 2 + m_wheelset) (each bogie carries half the body
    on its two axles). Tolerance 1e-6 relative: the static solve is exact up to the contact's
    penalty (wheel loads sum to the weight to 1e-9, tests/builder/test_builder_static.py)."""
    import tb_exudyn as tbx

    det = tbx.load_results(out / "det")
    car = det.scenario.train.vehicles[0]
    g = det.scenario.analysis.gravity
    expected = g * (car.body.mass / 4 + car.bogie.mass / 2 + car.wheelset.mass)
    got = det["car1.axle1.left.force_z"][0] + det["car1.axle1.right.force_z"][0]
    assert abs(got - expected) < 1e-6 * expected, (got, expected)


def _psd_integrates_to_sigma(out: Path) -> None:
    """li_zhu_2011_psd_maps: the saved PSD map is one-sided per Hz on the grid's quadrature, so
    sum_k S(f_k, t) df_k = sigma^2(t) for every channel and time (the PEM identity). Tolerance 1e-5
    of each channel's max sigma^2: the map is stored in float32 (relative rounding 6e-8 per cell)."""
    import numpy as np

    import tb_exudyn as tbx

    pem = tbx.load_results(out / "pem")
    assert pem.psd is not None
    kept = pem.psd_channels or pem.channels
    std = pem.std[[pem.index(c) for c in kept]]
    var = np.einsum("cft,f->ct", pem.psd.astype(float), pem.df)
    scale = (std ** 2).max(axis=1, keepdims=True)
    assert len(kept) >= 6 and np.max(np.abs(var - std ** 2) / np.maximum(scale, 1e-300)) < 1e-5


def _monte_carlo_within_its_band(out: Path) -> None:
    """li_zhu_2011_verification: Monte Carlo's sigma over PEM's lies within the band 1 +- 3/sqrt(2N)
    the sample size explains, at 90 % of the compared times or more, on each of the three channels
    (a factor sqrt(2) in the sampled amplitudes, or a one-/two-sided PSD mix-up, puts it outside
    everywhere)."""
    import tb_exudyn as tbx

    pem, mc = tbx.load_results(out / "pem"), tbx.load_results(out / "mc")
    comparison = tbx.compare(pem, mc)
    for row in comparison.rows:
        assert row.inside >= 0.9, (row.channel, row.inside, row.ratio_median)


def _imported_bridge_is_fryba(out: Path) -> None:
    """imported_modal_bridge: the saved run over the bridge read from the tables the script wrote (a
    20 m span's four vertical modes, kind modal_table) against Fryba's closed form as the FE bridge's test
    writes it (tests/builder/test_builder_fryba.py: the same span, force and modes), within 1e-3 of the
    peak (measured 4e-5 at the quick run's dt = 2e-4 s)."""
    import numpy as np

    import tb_exudyn as tbx
    from tests.builder.test_builder_fryba import fryba_midspan

    det = tbx.load_results(out / "alpha_1" / "det")
    sc = det.scenario
    assert sc.bridge.kind == "modal_table" and Path(sc.bridge.shapes).name == "shapes.csv"
    ref = -fryba_midspan(det.time - sc.track.lead_in / sc.speed, sc.speed, 4)
    assert np.abs(det["bridge.span1.mid.disp_z"] - ref).max() <= 1e-3 * np.abs(ref).max()


#: per script: checks of the numbers its --quick run writes (closed forms and identities)
NUMBERS = {
    "build_scenario_in_python.py": (_static_axle_load,),
    "li_zhu_2011_psd_maps.py": (_psd_integrates_to_sigma,),
    "li_zhu_2011_verification.py": (_monte_carlo_within_its_band,),
    "imported_modal_bridge.py": (_imported_bridge_is_fryba,),
}


def test_envelopes_from_saved_psd_result(tmp_path: Path, psd_maps_run):
    """The envelope script draws from the PSD-map script's saved result without a second sweep."""
    proc, _, maps = psd_maps_run
    check_ran(proc, EXAMPLES / "li_zhu_2011_psd_maps.py")
    env = tmp_path / "env"
    proc, seconds = run_script(EXAMPLES / "li_zhu_2011_envelopes.py", "--from", str(maps), "--out", str(env))
    check_ran(proc, EXAMPLES / "li_zhu_2011_envelopes.py")
    assert (env / "envelopes.csv").exists() and not (env / "pem").exists()  # loaded, not recomputed
    assert "loaded from" in proc.stdout
    header, *rows = (env / "envelopes.csv").read_text().splitlines()
    assert header.startswith("figure,channel,unit,") and len(rows) == 11


def test_envelopes_from_missing_folder_fails_clearly(tmp_path: Path):
    proc, _ = run_script(EXAMPLES / "li_zhu_2011_envelopes.py", "--from", str(tmp_path / "nothing"),
                         "--out", str(tmp_path / "env"))
    assert proc.returncode != 0 and "no PEM result" in proc.stderr


def test_default_output_is_under_examples_out():
    """Without --out, each of these examples writes under ./examples_out/<name> (ignored by git)."""
    for name in ("build_scenario_in_python", "li_zhu_2011_psd_maps", "li_zhu_2011_envelopes", "speed_sweep"):
        proc = subprocess.run([sys.executable, str(EXAMPLES / f"{name}.py"), "--help"], capture_output=True,
                              text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert f"examples_out/{name}" in proc.stdout, proc.stdout


def test_psd_maps_engines_agree(tmp_path: Path, psd_maps_run):
    """With the batched engine as the default, the Exudyn engine (the reference) runs the same quick
    setting through the same script and gives the same sigma."""
    proc, _, batched_out = psd_maps_run
    check_ran(proc, EXAMPLES / "li_zhu_2011_psd_maps.py")
    help_text = subprocess.run([sys.executable, str(EXAMPLES / "li_zhu_2011_psd_maps.py"), "--help"],
                               capture_output=True, text=True, timeout=120).stdout
    if "--engine" not in help_text:
        pytest.skip("run_pem has no engine option: the scripts use the Exudyn engine only")
    import numpy as np

    import tb_exudyn as tbx

    out = tmp_path / "exudyn"
    proc, _ = run_script(EXAMPLES / "li_zhu_2011_psd_maps.py", "--quick", "--engine", "exudyn", "--out", str(out))
    check_ran(proc, EXAMPLES / "li_zhu_2011_psd_maps.py")
    ex, ba = tbx.load_results(out / "pem"), tbx.load_results(batched_out / "pem")
    assert ex.provenance["engine"] == "exudyn" and ba.provenance["engine"] == "batched"
    assert ex.channels == ba.channels
    scale = ex.std.max(axis=1, keepdims=True)
    assert np.max(np.abs(ex.std - ba.std) / scale) < 1e-3
