"""Resource limits before work starts (issue 15): absurd values refused with the key named, memory
estimates refused against --max-memory (or the machine), workers capped at the cores.

Problem: the tiny sprung-mass scenario of execution_helpers with one value changed, and the quick
scenario (51 channels, 213 output times) with 100 000 frequencies (a PSD map of 8.7 GB). A refusal
must come before the allocation it guards: the refusing process stays far below that size
(measured with getrusage on the child).
"""

from __future__ import annotations

import re
import subprocess
import sys
import warnings

import pytest

from tb_exudyn.errors import ResourceError, SettingError
from tb_exudyn.execution import Execution, RunNotice
from tb_exudyn.execution.resources import MemoryEstimate, MemoryLimit, Part, check_memory, parse_memory

from .execution_helpers import ROOT, assert_one_line_error, cli, env, run_args, write_scenario

pytestmark = pytest.mark.exudyn


@pytest.mark.parametrize("change, key", [
    ({"time_step": 1e-300, "output_step": 0.01}, "analysis.time_step"),
    ({"time_step": 1e-9, "output_step": 0.01}, "analysis.time_step"),
    ({"lead_in": 1e308}, "track.lead_in"),
    ({"output_step": 1000.0}, "analysis.output_step"),
], ids=["time_step_1e-300", "time_step_1e-9", "lead_in_1e308", "output_step_1000"])
def test_an_absurd_run_length_is_refused_with_its_key(tmp_path, change, key):
    sc = write_scenario(tmp_path / "sc.toml", **change)
    proc = cli(*run_args(sc, tmp_path / "out"), timeout=300)  # a hang guard: generous under load
    line = assert_one_line_error(proc, f"key '{key}'", "allowed")
    assert line.split(": key")[0].endswith((str(sc), "scenario 'tiny'")), line  # the file (or the scenario's name)
    assert not (tmp_path / "out" / "pem").exists() and not (tmp_path / "out" / "checkpoint").exists()


def child_peak_bytes_of(args: list[object], timeout: float = 120) -> tuple[subprocess.CompletedProcess, int]:
    """Run the command in a child; its completed process and its peak resident memory [bytes]."""
    code = ("import resource, subprocess, sys; p = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
            "sys.stdout.write(p.stdout); sys.stderr.write(p.stderr); "
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024, file=sys.stdout); "
            "sys.exit(p.returncode)")
    proc = subprocess.run([sys.executable, "-c", code, sys.executable, "-m", "tb_exudyn", *map(str, args)],
                          capture_output=True, text=True, env=env(), cwd=ROOT, timeout=timeout)
    return proc, int(proc.stdout.strip().splitlines()[-1])


def test_a_psd_map_beyond_the_memory_limit_is_refused_before_it_is_allocated(tmp_path):
    """quick on 100 000 linear frequencies with every channel's PSD map kept (--psd-channels all): a
    map of 60 result channels x 100000 x 213 output times in float32 (5.1 GB) in the main process;
    with --max-memory 2GB refused naming analysis.n_freq and the estimate; the process never held
    more than 600 MB (the interpreter, one model, the task list)."""
    text = (ROOT / "models" / "scenarios" / "quick.toml").read_text(encoding="utf-8")
    text = re.sub(r"(?m)^n_freq = .*$", "n_freq = 100000", text)
    text = re.sub(r"(?m)^freq_spacing = .*$", 'freq_spacing = "linear"', text)
    sc = tmp_path / "big.toml"
    sc.write_text(text, encoding="utf-8")
    proc, peak = child_peak_bytes_of(run_args(sc, tmp_path / "out", "--max-memory", "2GB", "--psd-channels", "all"))
    line = assert_one_line_error(proc, "key 'analysis.n_freq' = 100000", "the PSD map", "float32",
                                 "--max-memory of 2 GB")
    assert re.search(r"the PSD map \(60 channels x 100000 frequencies x 213 output times, float32\) \(5\.11 GB in the "
                     r"main process\)", line), line
    assert "--psd-channels" in line
    assert "GB of memory" in line
    assert peak < 600e6, f"the refusal came after {peak / 1e6:.0f} MB were allocated"


def test_kept_samples_beyond_the_limit_are_refused_naming_the_samples(tmp_path):
    sc = write_scenario(tmp_path / "sc.toml")
    proc = cli(*run_args(sc, tmp_path / "out", "--method", "mc", "--samples", "10000000", "--keep-samples",
                         "--max-memory", "4GB"))
    assert_one_line_error(proc, "key 'keep_samples'", "the kept samples (10000000 samples", "--samples")


def test_a_max_memory_below_one_interpreter_is_refused_naming_the_option(tmp_path):
    sc = write_scenario(tmp_path / "sc.toml")
    proc = cli(*run_args(sc, tmp_path / "out", "--max-memory", "1MB"))
    assert_one_line_error(proc, "command line: key '--max-memory'", "at least")


@pytest.mark.parametrize("text", ["lots", "-3GB", "1e400", "4 parsecs", ""])
def test_a_bad_max_memory_is_a_setting_error(text):
    with pytest.raises(SettingError, match="max_memory"):
        parse_memory(text, "run_pem", "max_memory")


def test_memory_sizes_parse():
    assert parse_memory("4GB", "x", "k") == 4 * 10**9 and parse_memory("512 MiB", "x", "k") == 512 * 2**20
    assert parse_memory(2e9, "x", "k") == 2 * 10**9 and parse_memory(None, "x", "k") is None


def test_the_message_names_the_largest_part_and_fewer_workers_when_workers_hold_it():
    est = MemoryEstimate(parent=(Part("a", 10), Part("interpreter", 100)),
                         worker=(Part("the task's map", 5000, "analysis.n_freq", 400, "a smaller analysis.n_freq"),
                                 Part("interpreter", 100)), workers=2)
    assert est.total == 110 + 2 * 5100
    with pytest.raises(ResourceError) as info:
        check_memory(est, MemoryLimit(1000, "the limit"), "sc.toml")
    text = str(info.value)
    assert text.startswith("sc.toml: key 'analysis.n_freq' = 400")
    assert "the task's map (5 kB in each of 2 workers)" in text
    assert "fewer workers (2 now)" in text and "\n" not in text
    check_memory(est, MemoryLimit(None, "unknown"), "sc.toml")  # no limit known: nothing refused


def test_run_monte_carlo_checks_n_samples_like_the_scenario_key(tmp_path):
    from tb_exudyn.methods import run_monte_carlo
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario(write_scenario(tmp_path / "sc.toml"))
    with pytest.raises(SettingError, match=r"run_monte_carlo: key 'n_samples' = 1000000000 .*<= 10000000"):
        run_monte_carlo(sc, n_samples=10**9, engine="batched", workers=1, progress=False)


def test_workers_beyond_the_cores_are_capped_with_a_notice():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ex = Execution(workers=1000, where="run_pem")
    notices = [str(w.message) for w in caught if issubclass(w.category, RunNotice)]
    assert ex.pool_workers == ex.cores
    assert len(notices) == 1 and "run_pem: workers = 1000" in notices[0] and f"{ex.cores} cores" in notices[0]
    # the command line names the library's key as its flag when it prints the notice (tb_exudyn.cli.flags)
    from tb_exudyn.cli.flags import notice_as_flags

    assert notice_as_flags(notices[0].replace("run_pem", "command line")).startswith("command line: --workers = 1000 ")


def test_the_reductions_buffers_count_in_the_estimate(tmp_path):
    """quick as shipped (key PSD maps) on 100 000 frequencies in one process: the PSD map is small
    (12 maps), but a task of 120 000 columns needs its columns' state (1.9 GB) and the PEM
    reduction's buffers at an output time (the derivative rows of the last three times, the
    derivative, the z rows: 0.95 GB). With --max-memory 4GB the run (4.6 GB) is refused naming
    analysis.n_freq before anything large is allocated; without the buffers in the estimate (3.5 GB)
    it was let through and failed with an allocation error part-way."""
    text = (ROOT / "models" / "scenarios" / "quick.toml").read_text(encoding="utf-8")
    sc = tmp_path / "big.toml"
    sc.write_text(re.sub(r"(?m)^n_freq = .*$", "n_freq = 100000", text), encoding="utf-8")
    proc, peak = child_peak_bytes_of(run_args(sc, tmp_path / "out", "--max-memory", "4GB", "--workers", "1"))
    assert_one_line_error(proc, "key 'analysis.n_freq' = 100000", "--max-memory of 4 GB")
    assert peak < 600e6, f"the refusal came after {peak / 1e6:.0f} MB were allocated"


def test_an_allocation_the_estimate_missed_is_one_line(monkeypatch, capsys):
    """The last net: a MemoryError anywhere in a command is exit 2 with one line naming the command
    and what to change, not a traceback (the estimate has a margin, not a guarantee)."""
    from tb_exudyn import cli as cli_module

    def boom(args):
        raise MemoryError("Unable to allocate 106. MiB for an array with shape (58, 120000)")

    args = cli_module.build_parser().parse_args(["run", "quick"])
    args.func = boom  # the command itself fails; parsing and the checks of the arguments are the real ones
    monkeypatch.setattr(cli_module, "build_parser", lambda: type("P", (), {"parse_args": lambda self, argv: args})())
    code = cli_module.main(["run", "quick"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith("tb-exudyn: error: command 'run': out of memory (Unable to allocate 106. MiB"), err
    assert "--workers" in err[0] and "--resume" in err[0] and "Traceback" not in err[0]


def test_the_estimate_is_close_to_the_measured_peak(tmp_path):
    """quick with 1000 frequencies, in one process: the estimate (the kept PSD map in float32, the
    task's map and columns, the interpreter and model) against the child's own peak resident memory
    (VmHWM). Measured -3 % (191 MB against 197 MB); allowed -10 % .. +25 %, the margin of an
    estimate that must not refuse what fits, nor let through what does not."""
    code = f"""
import warnings
warnings.simplefilter("ignore")
import tb_exudyn as tbx
from tb_exudyn.methods import run_pem
from tb_exudyn.methods.pem import method as pem  # where the PEM worker checks its memory
seen = {{}}
real = pem.check_memory
pem.check_memory = lambda est, limit, where: (seen.update(total=est.total), real(est, limit, where))
sc = tbx.load_scenario("quick")
sc = sc.replace(analysis=sc.analysis.replace(n_freq=1000))
run_pem(sc, engine="batched", workers=1, progress=False)
# VmHWM: this process's own peak (ru_maxrss of a forked and exec'd child starts at the parent's size:
# Linux carries the old address space's high-water mark across exec, so a large pytest process inflates it)
hwm_kb = int(open("/proc/self/status").read().split("VmHWM:")[1].split()[0])
print(seen["total"], hwm_kb * 1024)
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env(), cwd=ROOT,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    estimate, peak = map(int, proc.stdout.split())
    assert 0.9 * peak <= estimate <= 1.25 * peak, (estimate / 1e6, peak / 1e6)


def test_too_many_tasks_are_refused_before_they_are_made(tmp_path):
    """The Exudyn engine runs a task per sample: 2 million samples are 2 million task objects (and
    checkpoint files); refused naming n_samples and the linear engine, before any is made."""
    from tb_exudyn.methods import run_monte_carlo
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario(write_scenario(tmp_path / "sc.toml"))
    with pytest.raises(ResourceError, match=r"key 'n_samples' = 2000000: 2e\+06 tasks .*'batched'"):
        run_monte_carlo(sc, n_samples=2_000_000, engine="exudyn", workers=1, progress=False)
