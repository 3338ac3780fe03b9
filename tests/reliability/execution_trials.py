"""Trials of the execution layer (issue 15): the cases of the issue's table, run against a code tree.

usage (from a worktree root): python -m tests.reliability.execution_trials CODE_DIR OUT.json [CASE ...]

CODE_DIR is the tree whose ``tb_exudyn`` is tried (e.g. an exported base commit: ``git archive 608e341 |
tar -x -C /tmp/base``); every run is a child process started there. Each case prints its name, its
class and a note; OUT.json collects them. Classes: clear (exit 2, one line naming the key or file;
or exit 130 for Ctrl-C), ok-notice (exit 0, the right result, a notice naming the file), ok (right,
nothing to say), traceback, wrong (exit 0 with a wrong or mixed result), lost (finished work
deleted), hang (no refusal within the time limit), unsupported (no such option), orphans.
Resource cases run under ``prlimit --as=4GB`` so that a case that is not refused cannot take the
machine. Not a test: it takes several minutes and runs a base tree too.
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

CODE = Path(sys.argv[1]).resolve()
OUT = Path(sys.argv[2])
ONLY = sys.argv[3:]
S = Path(os.environ.get("TRIALS_DIR", "/tmp/tb_exudyn_trials"))
W = S / ("trial-" + CODE.name)
PY = sys.executable
S.mkdir(parents=True, exist_ok=True)
from .execution_helpers import alive, descendants, snapshot, wait_for, write_scenario  # noqa: E402

TINY = write_scenario(S / "tiny.toml")
SLOW = write_scenario(S / "slow.toml", name="slow", lead_in=200.0, n_freq=30)
OTHER = write_scenario(S / "other.toml", name="other", speed=250.0)
ENV = {**os.environ, "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "PYTHONPATH": str(CODE)}


def run(args, timeout=120, limit_gb=None, new_session=False):
    cmd = [PY, "-m", "tb_exudyn", *map(str, args)]
    if limit_gb:
        cmd = ["prlimit", f"--as={int(limit_gb * 2**30)}", *cmd]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=CODE, env=ENV, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr, time.time() - t0
    except subprocess.TimeoutExpired as e:
        text = [x.decode(errors="replace") if isinstance(x, bytes) else (x or "") for x in (e.stdout, e.stderr)]
        return "timeout", text[0], text[1], time.time() - t0


def py(code, timeout=120, limit_gb=None):
    cmd = [PY, "-c", code]
    if limit_gb:
        cmd = ["prlimit", f"--as={int(limit_gb * 2**30)}", *cmd]
    try:
        p = subprocess.run(cmd, cwd=CODE, env=ENV, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        return "timeout", "", (e.stderr or b"").decode() if isinstance(e.stderr, bytes) else (e.stderr or "")


def _keeps_checkpoints() -> list[str]:
    """["--keep-checkpoint"] where the tree removes a checkpoint after a successful save (the
    checkpoint trials damage a finished run's checkpoint, so it must stay), else []."""
    p = subprocess.run([PY, "-m", "tb_exudyn", "run", "--help"], cwd=CODE, env=ENV, capture_output=True, text=True)
    return ["--keep-checkpoint"] if "--keep-checkpoint" in p.stdout else []


KEEP = _keeps_checkpoints()


def pem_run(out, sc=TINY, *extra, engine="batched", workers=1, timeout=120, **kw):
    return run(["run", sc, "--engine", engine, "--workers", workers, "--out", out, "--no-figures", "--no-progress",
                *KEEP, *extra], timeout=timeout, **kw)


def std_of(folder):
    code = (f"import numpy as np, sys; from tb_exudyn.results import load_results; r=load_results({str(folder)!r}); "
            "np.save(sys.stdout.buffer, r.std)")
    p = subprocess.run([PY, "-c", code], cwd=CODE, env=ENV, capture_output=True)
    if p.returncode != 0:
        return None
    import io
    import numpy as np
    return np.load(io.BytesIO(p.stdout))


def same(a, b):
    import numpy as np
    return a is not None and b is not None and a.shape == b.shape and np.allclose(a, b, rtol=1e-12, atol=0)


def fresh(name):
    d = W / name
    if d.exists():
        shutil.rmtree(d)
    d.parent.mkdir(parents=True, exist_ok=True)
    return d


def classify(rc, err, *, expect_names=(), ok_result=None):
    """clear: exit 2 (one-line error naming what is expected) or exit 0 with a right result and a
    notice naming the file; traceback; wrong: exit 0 and a wrong result."""
    if rc == "timeout":
        return "hang"
    if "Traceback" in err:
        return "traceback"
    if rc == 2:
        lines = [l for l in err.strip().splitlines() if l.strip()]
        named = all(any(n in l for l in lines) for n in expect_names)
        return "clear" if named else "unclear"
    if rc == 0:
        if ok_result is False:
            return "wrong"
        named = all(n in err for n in expect_names)
        return "ok-notice" if named else "ok-silent"
    return f"exit {rc}"


REF = {}


def ref(sc=TINY):
    if sc not in REF:
        d = fresh("ref-" + sc.stem)
        rc, o, e, _ = pem_run(d, sc, engine="exudyn" if sc == SLOW else "batched")
        assert rc == 0, e
        REF[sc] = std_of(d / "pem")
    return REF[sc]


def done_run(name, sc=TINY):
    d = fresh(name)
    rc, o, e, _ = pem_run(d, sc)
    assert rc == 0, e
    return d


def resume_case(name, damage, expect_names=()):
    d = done_run(name)
    target = damage(d)
    rc, o, e, _ = pem_run(d, TINY, "--resume")
    good = same(std_of(d / "pem"), ref())
    cls = classify(rc, e, expect_names=[*expect_names, *( [target.name] if target else [])], ok_result=good if rc == 0 else None)
    rc2, o2, e2, _ = pem_run(d, TINY, "--resume")
    later = "later resume ok" if rc2 == 0 and same(std_of(d / "pem"), ref()) else f"later resume FAILS ({rc2})"
    return cls, f"rc={rc}; {later}; {last(e)}"


def last(err, n=1):
    lines = [l for l in err.strip().splitlines() if l.strip() and "Warning" not in l and "warnings.warn" not in l]
    return " | ".join(lines[-n:])[:300]


TASK = "checkpoint/tasks/pemb-00002-00004.npz"


def c_truncated():
    def dmg(d):
        p = d / TASK
        data = p.read_bytes()
        p.write_bytes(data[: len(data) // 2])
        return p
    return resume_case("c_trunc", dmg)


def c_emptied():
    def dmg(d):
        p = d / TASK
        p.write_bytes(b"")
        return p
    return resume_case("c_empty", dmg)


def c_flipped():
    def dmg(d):
        p = d / TASK
        data = bytearray(p.read_bytes())
        for k in range(len(data) // 3, len(data) // 3 + 8):
            data[k] ^= 0xFF
        p.write_bytes(bytes(data))
        return p
    return resume_case("c_flip", dmg)


def c_flipped_header():
    def dmg(d):
        p = d / TASK
        data = bytearray(p.read_bytes())
        i = data.find(b"'shape': (")
        data[i + 10: i + 12] = b"99"
        p.write_bytes(bytes(data))
        return p
    return resume_case("c_fliph", dmg)


def c_garbage_manifest():
    def dmg(d):
        (d / "checkpoint/manifest.json").write_bytes(b"\x00{{garbage\xff")
        return None
    return resume_case("c_manifest", dmg, expect_names=["manifest.json"])


def c_foreign_tasks():
    other = done_run("c_other1", OTHER)
    def dmg(d):
        for f in (other / "checkpoint/tasks").glob("*.npz"):
            shutil.copy(f, d / "checkpoint/tasks" / f.name)
        return None
    return resume_case("c_foreign", dmg, expect_names=["pemb-00002-00004.npz"])


def c_foreign_no_manifest():
    other = done_run("c_other2", OTHER)
    def dmg(d):
        shutil.rmtree(d / "checkpoint")
        shutil.copytree(other / "checkpoint", d / "checkpoint")
        (d / "checkpoint/manifest.json").unlink()
        return None
    return resume_case("c_foreign_nm", dmg, expect_names=["pemb-00002-00004.npz"])


def c_rescaled():
    def dmg(d):
        p = d / TASK
        code = (f"import numpy as np; p={str(p)!r}; z=dict(np.load(p)); "
                "[z.__setitem__(k, z[k] * 2) for k in ('var_t', 'psd', 'var_z', 'psd_z') if k in z]; np.savez(p, **z)")
        subprocess.run([PY, "-c", code], check=True)
        return p
    return resume_case("c_rescale", dmg)


def c_key_swap():
    def dmg(d):
        shutil.copy(d / "checkpoint/tasks/pemb-00000-00001.npz", d / TASK)
        return d / TASK
    return resume_case("c_swap", dmg)


def c_mean_foreign():
    other = done_run("c_other3", OTHER)
    def dmg(d):
        shutil.copy(other / "checkpoint/tasks/pem-mean.npz", d / "checkpoint/tasks/pem-mean.npz")
        return d / "checkpoint/tasks/pem-mean.npz"
    return resume_case("c_mean", dmg)


def c_symlink_zero():
    def dmg(d):
        p = d / TASK
        p.unlink()
        p.symlink_to("/dev/zero")
        return p
    return resume_case("c_zero", dmg)


def c_fifo():
    d = done_run("c_fifo")
    p = d / TASK
    p.unlink()
    os.mkfifo(p)
    rc, o, e, _ = pem_run(d, TINY, "--resume", timeout=30)
    return classify(rc, e, expect_names=[p.name], ok_result=same(std_of(d / "pem"), ref()) if rc == 0 else None), \
        f"rc={rc}; {last(e)}"


def c_keep_samples_change():
    d = fresh("c_keep")
    code = ("import warnings; warnings.simplefilter('ignore'); import tb_exudyn as t; from tb_exudyn.methods import run_monte_carlo as mc\n"
            "from tb_exudyn.errors import UserError\n"
            f"sc=t.load_scenario({str(TINY)!r}); mc(sc, n_samples=4, engine='batched', workers=1, out={str(d)!r}, progress=False)\n"
            "try:\n"
            f"    r=mc(sc, n_samples=4, engine='batched', workers=1, out={str(d)!r}, progress=False, resume=True, keep_samples=True)\n"
            "except UserError as e:\n    print('USERERROR', e); raise SystemExit(2)\n"
            "print('samples', None if r.samples is None else r.samples.shape)")
    rc, o, e = py(code)
    if rc == 2 and "USERERROR" in o:
        return "clear", o.strip()[:300]
    if rc == 0 and "samples (4," in o:
        return "ok-silent", "rc=0; samples kept"
    return ("traceback" if "Traceback" in e else f"exit {rc}"), f"rc={rc}; {last(e)}"


# ------------------------------------------------------------------ folders
def start(args, **kw):
    return subprocess.Popen([PY, "-m", "tb_exudyn", *map(str, args)], cwd=CODE, env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kw)


def slow_args(d, *extra, workers=1):
    return ["run", SLOW, "--engine", "exudyn", "--workers", workers, "--out", d, "--no-figures", "--no-progress", *extra]


def n_tasks(d, name="checkpoint"):
    return len(list((d / name / "tasks").glob("*.npz"))) if (d / name / "tasks").exists() else 0


def f_concurrent():
    d = fresh("f_conc")
    p1 = start(slow_args(d))
    wait_for(lambda: n_tasks(d) >= 2)
    rc, o, e, _ = run(slow_args(d), timeout=120)
    o1, e1 = p1.communicate(timeout=120)
    good1 = p1.returncode == 0 and same(std_of(d / "pem"), ref(SLOW))
    cls = classify(rc, e, expect_names=[str(d)])
    if rc == 0:
        cls = "wrong" if not good1 else "ok-silent (both ran)"
    return cls, f"second rc={rc}; first rc={p1.returncode}, first result {'right' if good1 else 'WRONG/none'}; {last(e)}"


def f_checkpoint_no_resume():
    d = fresh("f_cp")
    p1 = start(slow_args(d))
    wait_for(lambda: n_tasks(d) >= 4)
    os.kill(p1.pid, signal.SIGKILL)
    p1.wait()
    before = n_tasks(d)
    snap = snapshot(d)
    rc, o, e, _ = run(slow_args(d), timeout=120)
    lost = rc == 0  # the finished tasks of the killed run were deleted (a new run started)
    cls = "lost" if lost else classify(rc, e, expect_names=[str(d), "--resume"])
    changed = snapshot(d) != snap
    return cls, f"rc={rc}; {before} finished tasks before; folder {'CHANGED' if changed else 'unchanged'}; {last(e)}"


def f_results_again():
    d = done_run("f_again")
    snap = snapshot(d)
    rc, o, e, _ = pem_run(d, OTHER)
    changed = snapshot(d) != snap
    if rc == 0:
        return "silent overwrite", "rc=0; results replaced without a word"
    return classify(rc, e, expect_names=[str(d), "--overwrite"]), f"rc={rc}; folder {'CHANGED' if changed else 'unchanged'}; {last(e)}"


def f_overwrite():
    d = fresh("f_over")
    rc, o, e, _ = run(["run", TINY, "--engine", "batched", "--workers", 1, "--out", d, "--no-progress"], timeout=300)
    assert rc == 0, e
    figs = len(list(d.rglob("*.png")))
    (d / "mine.txt").write_text("user file")
    rc, o, e, _ = pem_run(d, OTHER, "--overwrite")
    if rc != 0:
        return ("unsupported" if "unrecognized" in e else classify(rc, e)), f"rc={rc}; {last(e)}"
    left = len(list(d.rglob("*.png")))
    good = same(std_of(d / "pem"), ref(OTHER))
    ok = left == 0 and (d / "mine.txt").exists() and good and not (d / "report.html").exists()
    return ("ok" if ok else "wrong"), f"{figs} figures before, {left} after; user file kept {(d / 'mine.txt').exists()}; result {'right' if good else 'WRONG'}"


def f_stale_lock():
    d = fresh("f_stale")
    p1 = start(slow_args(d))
    wait_for(lambda: n_tasks(d) >= 2)
    os.kill(p1.pid, signal.SIGKILL)
    p1.wait()
    rc, o, e, _ = run(slow_args(d, "--resume"), timeout=120)
    good = same(std_of(d / "pem"), ref(SLOW))
    return ("ok" if rc == 0 and good else classify(rc, e)), f"rc={rc}; result {'right' if good else 'WRONG/none'}; {last(e)}"


def f_resume_foreign():
    d = done_run("f_rf")
    rc, o, e, _ = pem_run(d, OTHER, "--resume")
    return classify(rc, e, expect_names=[str(d / "checkpoint")]), f"rc={rc}; {last(e)}"


# ------------------------------------------------------------------ resources
def variant(name, base=None, **changes):
    text = (base or TINY).read_text()
    for k, v in changes.items():
        import re
        text = re.sub(rf"^{k} = .*$", f"{k} = {v}", text, flags=re.M)
    p = W / f"{name}.toml"
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)
    return p


def resource_case(name, key, timeout=40, base=None, **changes):
    sc = variant(name, base, **changes)
    d = fresh(name)
    rc, o, e, dt = pem_run(d, sc, timeout=timeout, limit_gb=4)
    if rc == "timeout":
        return "hang", f"still running after {timeout} s (no refusal)"
    return classify(rc, e, expect_names=[key]), f"rc={rc} in {dt:.1f} s; {last(e)}"


def r_nfreq():
    return resource_case("r_nfreq", "n_freq", base=CODE / "models/scenarios/quick.toml", n_freq=100000)


def r_nfreq_fits():
    sc = variant("r_nfreq_fits", n_freq=100000)
    d = fresh("r_nfreq_fits")
    rc, o, e, dt = pem_run(d, sc, timeout=120, limit_gb=4)
    return ("ok" if rc == 0 else classify(rc, e)), f"rc={rc} in {dt:.1f} s (2 channels x 1e5 frequencies x 49 times fits); {last(e)}"


def r_nfreq_channels():
    return resource_case("r_nfreq2", "n_freq", n_freq=20000, channels='["*"]')


def r_output_step():
    return resource_case("r_ostep", "output_step", output_step=1000.0)


def r_tiny_step():
    return resource_case("r_tstep", "time_step", time_step=1e-300)


def r_nano_step():
    return resource_case("r_nstep", "time_step", time_step=1e-9)


def r_lead_in():
    return resource_case("r_lead", "lead_in", lead_in=1e308)


def r_workers():
    d = fresh("r_workers")
    rc, o, e, dt = pem_run(d, TINY, workers=1000, timeout=120)
    notice = "--workers" in e or "cores" in e
    return ("ok-notice" if rc == 0 and notice else ("ok-silent" if rc == 0 else classify(rc, e))), f"rc={rc} in {dt:.1f} s; {last(e)}"


def r_max_memory():
    d = fresh("r_maxmem")
    rc, o, e, dt = pem_run(d, TINY, "--max-memory", "1MB")
    if "unrecognized" in e:
        return "unsupported", "no --max-memory option"
    return classify(rc, e, expect_names=["--max-memory"]), f"rc={rc}; {last(e)}"


def r_samples_api():
    d = fresh("r_samples")
    code = ("import warnings; warnings.simplefilter('ignore'); import tb_exudyn as t; from tb_exudyn.methods import run_monte_carlo as mc\n"
            "from tb_exudyn.errors import UserError\n"
            f"sc=t.load_scenario({str(TINY)!r})\n"
            "try:\n"
            f"    mc(sc, n_samples=10**9, engine='batched', workers=1, out={str(d)!r}, progress=False)\n"
            "except UserError as e:\n    print('USERERROR', e); raise SystemExit(2)\n")
    rc, o, e = py(code, timeout=40, limit_gb=4)
    if rc == 2:
        return ("clear" if "n_samples" in o else "unclear"), o.strip()[:300]
    return ("hang" if rc == "timeout" else ("traceback" if "Traceback" in e else f"exit {rc}")), f"rc={rc}; {last(e)}"


def r_keep_samples_api():
    d = fresh("r_keep")
    code = ("import warnings; warnings.simplefilter('ignore'); import tb_exudyn as t; from tb_exudyn.methods import run_monte_carlo as mc\n"
            "from tb_exudyn.errors import UserError\n"
            f"sc=t.load_scenario({str(TINY)!r})\n"
            "try:\n"
            f"    mc(sc, n_samples=10**7, keep_samples=True, engine='batched', workers=1, out={str(d)!r}, progress=False)\n"
            "except UserError as e:\n    print('USERERROR', e); raise SystemExit(2)\n")
    rc, o, e = py(code, timeout=40, limit_gb=4)
    if rc == 2:
        return ("clear" if "keep_samples" in o or "n_samples" in o else "unclear"), o.strip()[:300]
    return ("hang" if rc == "timeout" else ("traceback" if "Traceback" in e else f"exit {rc}")), f"rc={rc}; {last(e)}"


def r_samples_cli():
    d = fresh("r_samples_cli")
    rc, o, e, dt = run(["run", TINY, "--method", "mc", "--engine", "batched", "--samples", "1000000000", "--workers", 1,
                        "--out", d, "--no-figures", "--no-progress"], timeout=40, limit_gb=4)
    if rc == "timeout":
        return "hang", "still running after 40 s"
    return classify(rc, e, expect_names=["--samples"]), f"rc={rc} in {dt:.1f}; {last(e)}"


# ------------------------------------------------------------------ lifecycle
def l_ctrl_c(early=None):
    d = fresh("l_ctrlc")
    p = start(slow_args(d, workers=2), start_new_session=True)
    if early is None:
        wait_for(lambda: n_tasks(d) >= 2, 90)
    else:
        time.sleep(early)
    kids = descendants(p.pid)
    os.killpg(p.pid, signal.SIGINT)  # as a terminal does: the whole foreground group
    try:
        o, e = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        return "hang", "not ended 30 s after Ctrl-C"
    time.sleep(5)
    left = alive(kids)
    lines = [l for l in e.strip().splitlines() if l.strip() and "Warning" not in l and "warnings.warn" not in l]
    ok = p.returncode == 130 and "Traceback" not in e and len(lines) == 1 and not left
    return ("clear" if ok else ("traceback" if "Traceback" in e else f"exit {p.returncode}")), \
        f"rc={p.returncode}; {len(lines)} stderr lines; {len(left)} of {len(kids)} children alive after 5 s; {last(e)}"


def l_ctrl_c_startup():
    return l_ctrl_c(early=2.0)


def l_ctrl_c_setup():
    return l_ctrl_c(early=3.5)


def l_sigkill_parent():
    d = fresh("l_kill")
    p = start(slow_args(d, workers=2))
    wait_for(lambda: n_tasks(d) >= 2, 90)
    kids = descendants(p.pid)
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    time.sleep(5)
    left = alive(kids)
    for k in left:
        try:
            os.kill(k, signal.SIGKILL)
        except OSError:
            pass
    return ("ok" if not left else "orphans"), f"{len(left)} of {len(kids)} child processes alive 5 s after SIGKILL of the parent"


def l_worker_error():
    sc = variant("l_nomatch", channels='["bridge.nomatch.*"]')
    d = fresh("l_err")
    rc, o, e, dt = pem_run(d, sc, workers=2)
    lines = [l for l in e.strip().splitlines() if l.strip() and "Warning" not in l and "warnings.warn" not in l]
    cls = classify(rc, e, expect_names=["analysis.channels"])
    return (cls if len(lines) == 1 or cls != "clear" else "unclear"), f"rc={rc} in {dt:.1f} s; {len(lines)} lines; {last(e)}"


def k_sweep():
    d = fresh("k_sweep")
    p = start(slow_args(d))
    wait_for(lambda: n_tasks(d) >= 3, 90)
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    rc, o, e, _ = run(slow_args(d, "--resume"))
    good = same(std_of(d / "pem"), ref(SLOW))
    return ("ok" if rc == 0 and good else "wrong"), f"rc={rc}; resumed result {'right' if good else 'WRONG'}"


def k_final_save():
    """An old result in the folder; a new run (--overwrite when the option exists, else plain) is killed
    right after the first file of the final save is renamed into place; then load, then --resume."""
    d = done_run("k_save", OTHER)
    old = std_of(d / "pem")
    has_over = "--overwrite" in run(["run", "--help"])[1]
    extra = ["--overwrite"] if has_over else []
    code = ("import os, signal, sys\n"
            "real = os.replace\n"
            "def rep(a, b):\n"
            "    real(a, b)\n"
            f"    if str(b).startswith({str(d / 'pem')!r}):\n"
            "        os.kill(os.getpid(), signal.SIGKILL)\n"
            "os.replace = rep\n"
            "real_rename = os.rename\n"
            "def ren(a, b):\n"
            "    real_rename(a, b)\n"
            f"    if str(b).startswith({str(d / 'pem')!r}):\n"
            "        os.kill(os.getpid(), signal.SIGKILL)\n"
            "os.rename = ren\n"
            "from tb_exudyn.cli import main\n"
            f"sys.exit(main(['run', {str(TINY)!r}, '--engine', 'batched', '--workers', '1', '--out', {str(d)!r}, "
            f"'--no-figures', '--no-progress', *{extra!r}]))\n")
    rc, o, e = py(code)
    after = std_of(d / "pem")
    meta_name = None
    try:
        meta_name = json.loads((d / "pem/meta.json").read_text())["scenario_toml"].split("\n")[1]
    except Exception:
        pass
    if after is None:
        state = "does not load"
    elif same(after, old) and "other" in str(meta_name):
        state = "old result"
    elif same(after, ref()) and "tiny" in str(meta_name):
        state = "new result"
    else:
        state = f"MIX (meta {meta_name}, arrays {'new' if same(after, ref()) else 'old' if same(after, old) else '?'})"
    rc2, o2, e2, _ = pem_run(d, TINY, "--resume")
    good = same(std_of(d / "pem"), ref())
    cls = "wrong" if state.startswith("MIX") else ("ok" if good and rc2 == 0 else "lost?")
    return cls, f"killed child rc={rc}; after kill: {state}; resume rc={rc2}, {'new complete result' if good else 'WRONG'}"


CASES = {n: f for n, f in list(globals().items()) if n[:2] in ("c_", "f_", "r_", "l_", "k_") and callable(f)}

if __name__ == "__main__":
    results = {}
    for name, fn in CASES.items():
        if ONLY and name not in ONLY:
            continue
        t0 = time.time()
        try:
            cls, note = fn()
        except Exception as exc:  # the harness itself
            cls, note = "harness-error", repr(exc)[:300]
        results[name] = {"class": cls, "note": note, "seconds": round(time.time() - t0, 1)}
        print(f"{name:26s} {cls:18s} {note}", flush=True)
    old = json.loads(OUT.read_text()) if OUT.exists() else {}
    old.update(results)
    OUT.write_text(json.dumps(old, indent=1))
