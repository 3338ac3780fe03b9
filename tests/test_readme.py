"""README.md's Python block runs as pasted into a file, and its commands are the CI's.

The block between the ``readme:python`` markers is written to a file in a fresh folder and run there
as a user would run it (``python my_study.py``: spawned worker processes need the
``if __name__ == "__main__":`` guard); it must exit 0 and write what it says it writes.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def readme_block(name: str, fence: str) -> str:
    """The code between ``<!-- NAME -->`` and ``<!-- /NAME -->`` in README.md, without the fences."""
    text = README.read_text(encoding="utf-8")
    start, stop = f"<!-- {name} -->", f"<!-- /{name} -->"
    assert start in text and stop in text, f"README.md has no {name} block"
    body = text.split(start, 1)[1].split(stop, 1)[0].strip()
    assert body.startswith(f"```{fence}") and body.endswith("```"), body[:40]
    return body[len(f"```{fence}"):-3].strip() + "\n"


def test_readme_has_the_two_ci_commands():
    for name in ("ci:main-job", "ci:tests"):
        assert "pip install" in readme_block(name, "bash")
    assert readme_block("ci:main-job", "bash").strip().endswith("tb-exudyn run")


@pytest.mark.exudyn
@pytest.mark.slow
def test_readme_python_block_runs_as_pasted(tmp_path):
    pytest.importorskip("exudyn")
    script = tmp_path / "my_study.py"
    script.write_text(readme_block("readme:python", "python"), encoding="utf-8")
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, script.name], cwd=tmp_path, capture_output=True, text=True,
                          timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (tmp_path / "my_study.toml").exists() and (tmp_path / "acc.png").stat().st_size > 1000
    assert (tmp_path / "my_study_out" / "pem" / "meta.json").exists()
