"""The built wheel installs into a fresh virtual environment and works from there.

Offline and quick: the wheel is built without build isolation (setuptools of
the running environment), installed with ``--no-deps`` into a bare venv whose
site-packages reaches this environment's dependencies through a ``.pth`` line
(a path line adds the folder only: this environment's editable install of the
package, itself a ``.pth`` hook, is not activated). The command then runs from
the installed copy, not from ``src/``: it prints its help and runs a small
simulation. The simulation runs with numba's JIT off: the kernels' Python
source executes from the installed copy, which is what this test is about
(every module and data file the command needs is in the wheel), while
compiling them afresh for the new source path would cost ~90 s on 2 cores
and test nothing the rest of the suite does not (the compiled kernels run
from ``src/`` there).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

CASE = """\
well: {profiles: {vertical: {kind: vertical, td_m: 200.0}}}
string:
  components:
    - {type: collar, name: DC, od_m: 0.17145, id_m: 0.0714, length_m: 20.0, n_segments: 2}
    - {type: drill_pipe, name: DP, od_m: 0.127, id_m: 0.1086, length_m: 40.0,
       tool_joint_od_m: 0.1683, n_segments: 4}
operation: {bit_md_m: 70.0, duration_s: 0.2, rpm: 100.0, rpm_ramp_s: 0.1, tob_Nm: 1000.0,
            rop_m_per_s: 0.01}
recording: {loads_rate_hz: 100.0, channels_rate_hz: 100.0, kinematics_rate_hz: 10.0}
"""


def _run(cmd: list[str], cwd: Path, env: dict[str, str], timeout: float = 600) -> str:
    out = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert out.returncode == 0, f"{cmd}:\n{out.stdout[-2000:]}\n{out.stderr[-3000:]}"
    return out.stdout


@pytest.mark.slow
def test_wheel_installs_and_runs_outside_the_source_tree(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    # build from a copy: an in-tree build would write build/ and *.egg-info into the checkout
    source = tmp_path / "source"
    shutil.copytree(ROOT / "src", source / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(ROOT / name, source / name)
    dist = tmp_path / "dist"
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
          "-w", str(dist), str(source)], tmp_path, env)
    (wheel,) = dist.glob("drillfatigue-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    # every subpackage, down to the law modules of a registry
    for name in ("drillfatigue/dynamics/step/integrator.py",
                 "drillfatigue/dynamics/contact/friction/laws/tanh_exp.py",
                 "drillfatigue/dynamics/bit/laws/dispatch.py", "drillfatigue/softstring/march.py"):
        assert name in names, name
    assert not any(n.startswith(("tests/", "testkit/")) or "/synthetic" in n for n in names)

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", str(venv)], tmp_path, env)
    py = venv / "bin" / "python"
    site = Path(_run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                     tmp_path, env).strip())
    (site / "_deps_of_the_test_environment.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    _run([sys.executable, "-m", "pip", "--python", str(py), "install", "--no-deps", "--no-index",
          "-q", str(wheel)], tmp_path, env)

    where = _run([str(py), "-c", "import drillfatigue; print(drillfatigue.__file__)"], tmp_path, env)
    assert Path(where.strip()).is_relative_to(venv), where

    exe = venv / "bin" / "drillfatigue"
    assert "simulate" in _run([str(exe), "--help"], tmp_path, env)
    (tmp_path / "case.yaml").write_text(CASE)
    _run([str(exe), "simulate", "case.yaml", "--out", "run"], tmp_path,
         {**env, "NUMBA_DISABLE_JIT": "1"})
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["duration_s"] == pytest.approx(0.2, abs=0.02)
    assert (tmp_path / "run" / "loads.parquet").stat().st_size > 0
