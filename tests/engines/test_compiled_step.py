"""The batched engine's compiled step (engines/batched/compiled.py) against its numpy step.

The compiled step makes the numpy step's BLAS gemm calls on the same arrays in the same order; its
update is the numpy step's seven axpy / scal passes fused into one loop (contracted to fused
multiply-adds where the CPU has them, as BLAS' axpy kernels but for one of the two orders of a~'s
sum), and the harmonic inputs' complex products and the bridge's diagonal terms are formed in
compiled code instead of numpy's ufuncs: the last bit of a step may differ. Both integrate the same
linear system with the same step, so their results agree to round-off carried through a stable
integration. Measured on li_zhu_2011 under OPENBLAS_CORETYPE Haswell, Zen, SkylakeX and Prescott:
sigma within 4.8e-13 of each channel's largest, the mean within 1.6e-11 of its largest |mean|, both
on the wheelsets (their accelerations are recovered from Delta, a small remainder of nearly
balanced stiff forces, which magnifies round-off: docs/speed.md section 1). The bounds, 1e-11 and
1e-10, are 20 and 6 times those and below the numpy step's own spread between two BLAS kernels
(Prescott against SkylakeX: 6.9e-10 on sigma, 7.1e-9 on the mean). In float32 each step carries
float32's own error, and the test bounds it by the numpy step's. The PSD map travels in float32
(methods/pseudo_reduction.PSD_TRANSPORT), where a round-off difference can flip its last bit:
2^-23 = 1.2e-7 of a value, the float64 bound of the maps.
"""

from __future__ import annotations

import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from .test_batched import _quick_car15, _relative

pytestmark = pytest.mark.exudyn


def _both(sc, precision: str = "float64"):  # noqa: ANN001, ANN202
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all",
                        options=BatchedOptions(step=step, precision=precision)) for step in ("numpy", "compiled")]


def _li_zhu_3():  # noqa: ANN202
    """The reference study (li_zhu_2011) on 3 linear frequencies x 3 types, every channel."""
    import tb_exudyn as tbx

    sc = tbx.load_scenario("li_zhu_2011")
    return sc.replace(analysis=sc.analysis.replace(n_freq=3, freq_spacing="linear", channels=("*",)))


def test_compiled_step_equals_numpy_step_on_four_cars_over_three_spans():
    """Problem: the reference study (4 cars, 3 spans on piers, 52 bridge modes, one component of
    160 coordinates) on 3 frequencies x 3 types, every channel, so that every branch of the step
    runs: vehicles at rest, on the approach (folded step, forces at output steps), entering, on and
    leaving the bridge (Woodbury over a changing range of vehicles), output steps at the last step
    of a block (16 steps, outputs every 10). Reference: the numpy step. Tolerance: module docstring."""
    ref, got = _both(_li_zhu_3())
    assert _relative(got.std, ref.std) < 1e-11
    assert _relative(got.psd, ref.psd) < 1.2e-7
    assert _relative(got.mean, ref.mean) < 1e-10  # the linear mean: its gravity column on each side's step
    assert got.provenance["step"] == "compiled" and ref.provenance["step"] == "numpy"


@pytest.mark.parametrize("name", ["li_zhu_2011", "li_zhu_2011_creep"])
def test_linear_mean_on_the_compiled_step_equals_the_numpy_step(name):
    """Problem: the batched engine's linear mean (the gravity column: a constant row input f_s, the
    constant generalised force F_c, C_b y_c on the bridge rows of each contact solve, Delta += y_c)
    of the reference study (penalty rows) and of its creep variant (general linear rows), over the
    whole crossing. Reference: the same column on the numpy step (run.py's solve). Tolerance: round-off
    (module docstring), 1e-10 of each channel's largest |mean| (measured 1.1e-11 .. 1.6e-11 on both
    scenarios under the Haswell, SkylakeX and Prescott kernels, the wheelsets' roll accelerations).
    The compiled side must have run compiled blocks."""
    import tb_exudyn as tbx
    from tb_exudyn.engines import make_engine
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.engines.batched import run as batched_run

    sc = tbx.load_scenario(name)
    blocks = []
    original = batched_run._Run.run_block

    def counted(self, *args, **kwargs):  # noqa: ANN001, ANN202
        blocks.append(1)
        return original(self, *args, **kwargs)

    means = {}
    with warnings.catch_warnings(), pytest.MonkeyPatch.context() as mp:
        warnings.simplefilter("ignore")
        mp.setattr(batched_run._Run, "run_block", counted)
        for step in ("numpy", "compiled"):
            blocks.clear()
            means[step] = make_engine("batched", sc, BatchedOptions(step=step)).mean()["mean"]
            assert bool(blocks) == (step == "compiled")
    ref, got = means["numpy"], means["compiled"]
    scale = np.abs(ref).max(axis=1, keepdims=True)
    assert np.all(np.abs(got - ref) <= 1e-10 * np.where(scale > 0, scale, 1.0))


def test_compiled_step_in_float32_is_as_close_to_float64_as_the_numpy_step():
    """Problem: as above in float32 (BatchedOptions(precision="float32")). Reference: the float64
    numpy step. In float32 the two steps' round-off differs from the first input on and each
    carries the float32 error (here up to 3e-4 of a channel's largest sigma on the axles'
    accelerations and the forces of the stiff contacts, measured with either step on this 3-frequency
    grid); so the bound is the numpy step's own float32 error with a margin of 1.5, and 1e-3 absolute."""
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    sc = _li_zhu_3()
    n32, c32 = _both(sc, "float32")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_pem(sc, workers=1, progress=False, engine="batched", options=BatchedOptions(step="numpy"))
    err_numpy, err_compiled = _relative(n32.std, ref.std), _relative(c32.std, ref.std)
    assert err_compiled < max(1.5 * err_numpy, 1e-6)
    assert err_compiled < 1e-3



def test_the_float32_compiled_step_casts_no_unset_value():
    """Problem: the compiled step in float32 on the reference study (as above). The contact inverses are
    formed in float64 into one buffer and cast to float32; a buffer made with np.empty left its unused
    tail unset, and the cast of that garbage overflowed: "RuntimeWarning: overflow encountered in cast"
    on the main job's terminal (its grid-error columns run in float32), twice. Reference: no warning
    of numpy's about a cast or an overflow (a warning is deterministic: no tolerance)."""
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_pem(_li_zhu_3(), workers=1, progress=False, engine="batched",
                options=BatchedOptions(step="compiled", precision="float32"))
    numeric = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)
               and ("overflow" in str(w.message) or "cast" in str(w.message))]
    assert not numeric, numeric

def test_compiled_step_equals_numpy_step_on_two_components():
    """Problem: one ICE motor car on the girder axis (scenario quick, track offset 0, 2 frequencies):
    two components (vertical in-plane; lateral and cross-level out-of-plane), each with its own
    operators and compiled runs, sharing the vertical contact rows. Reference: the numpy step.
    Tolerance: module docstring (float64)."""
    from tb_exudyn.engines.batched import BatchedEngine

    sc = _quick_car15(track_offset=0.0)
    assert len(BatchedEngine(sc).components) == 2
    ref, got = _both(sc)
    assert _relative(got.std, ref.std) < 1e-12
    assert _relative(got.psd, ref.psd) < 1.2e-7


def test_step_option_is_checked():
    """Problem: BatchedOptions(step="fortran"). Reference: the documented values. Exact (an error)."""
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.errors import SettingError

    with pytest.raises(SettingError, match="step"):
        BatchedOptions(step="fortran")


def test_cache_directory_follows_the_platform_and_the_user(monkeypatch, tmp_path):
    """Problem: where the compiled code goes. Reference: jit.cache_dir's rule (NUMBA_CACHE_DIR if
    set, else $XDG_CACHE_HOME/tb_exudyn/numba on Linux). Exact (paths)."""
    from tb_exudyn.jit import cache_dir

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    if sys.platform.startswith("linux"):
        assert cache_dir() == tmp_path / "tb_exudyn" / "numba"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "mine"))
    assert cache_dir() == tmp_path / "mine"


@pytest.mark.slow
def test_compiled_code_is_cached_in_the_user_cache_directory_only(tmp_path):
    """Problem: a fresh process (XDG_CACHE_HOME a new folder, no NUMBA_CACHE_DIR) runs PEM with the
    compiled step on one car, writing its result into an output folder; a second process does it
    again. Reference: the rule of jit.cache_dir: the compiled code lands in
    $XDG_CACHE_HOME/tb_exudyn/numba, nothing in the installed package or the output folder, and
    the second process loads it instead of compiling (its index files are not rewritten). Exact
    (files)."""
    import tb_exudyn

    package = Path(tb_exudyn.__file__).parent
    before = {p for p in package.rglob("*") if p.suffix in (".nbi", ".nbc")}
    code = ("import warnings, sys; warnings.simplefilter('ignore'); import tb_exudyn as tbx; "
            "from tb_exudyn.methods import run_pem; sc = tbx.load_scenario('quick'); "
            "sc = sc.replace(analysis=sc.analysis.replace(n_freq=2, freq_spacing='linear')); "
            "run_pem(sc, workers=1, progress=False, out=sys.argv[1], grid_error=False)")
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache")
    stamps = []
    for i in range(2):
        out = tmp_path / f"out{i}"
        subprocess.run([sys.executable, "-c", code, str(out)], env=env, check=True, cwd=str(tmp_path))
        cached = sorted((tmp_path / "cache" / "tb_exudyn" / "numba").rglob("*.nbi"))
        assert cached, "no compiled code in the user cache directory"
        stamps.append({p: p.stat().st_mtime_ns for p in cached})
        assert not [p for p in out.rglob("*") if p.suffix in (".nbi", ".nbc")]
    assert stamps[0] == stamps[1]
    assert {p for p in package.rglob("*") if p.suffix in (".nbi", ".nbc")} == before
