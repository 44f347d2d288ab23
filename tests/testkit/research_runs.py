"""A tiny research run for the research sweep's tests: 2 training cases and 1 held-out
case on a 0.75 s window (1.5 s when extended), run as the command line runs it."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml
from filelock import FileLock

from drillfatigue.numba_cache import source_digest

ROOT = Path(__file__).resolve().parents[2]
#: 2 training cases (a Sobol power of two) and 1 held-out case.
N_TRAIN, N_HELDOUT = 2, 1


def tiny_params(folder: Path) -> Path:
    """params.yaml with a 0.25 s ramp and a 0.75 s window (1.5 s when extended)."""
    p = yaml.safe_load((ROOT / "params.yaml").read_text(encoding="utf-8"))
    p["operation"]["rpm_ramp_s"] = 0.25
    p["recording"]["start_s"] = 0.25
    p["sweep"]["window_s"] = 0.75
    p["sweep"]["window"]["max_s"] = 1.5
    path = folder / "params.yaml"
    path.write_text(yaml.safe_dump(p, sort_keys=False), encoding="utf-8")
    return path


def command(params: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "drillfatigue", "dataset", "research", "--params", str(params),
            "--n-cases", str(N_TRAIN), "--heldout-cases", str(N_HELDOUT), "--out", str(out),
            "--workers", "2", "--no-progress"]


def env() -> dict[str, str]:
    return {**os.environ, "PYTHONWARNINGS": "ignore"}


def git(cwd: Path, *args: str) -> None:
    subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=cwd,
                   check=True, capture_output=True)


def case_files(out: Path) -> list[Path]:
    """Finished case files (an atomic write cut short leaves a hidden temporary file
    that the next run deletes)."""
    if not (out / "cases").is_dir():
        return []
    return sorted(p for p in (out / "cases").glob("*/*.parquet") if not p.name.startswith("."))


#: Uninterrupted tiny runs, one folder per :func:`_run_key`, shared by the test processes.
CACHE = ROOT / ".pytest_cache" / "tiny_research"


def _run_key(params: Path) -> str:
    """Digest of what the run reads: the params file, this file and the package's sources."""
    h = hashlib.sha256(Path(params).read_bytes())
    h.update(Path(__file__).read_bytes())
    h.update(source_digest(ROOT / "src" / "drillfatigue").encode())
    return h.hexdigest()[:20]


def full_run(folder: Path) -> tuple[Path, Path]:
    """An uninterrupted tiny run (params and research folder) copied into ``folder``: run
    once per params and source tree under a lock, as :func:`command` runs it, and copied
    for each test that needs one."""
    folder.mkdir(parents=True, exist_ok=True)
    params = tiny_params(folder)
    cached = CACHE / _run_key(params)
    CACHE.mkdir(parents=True, exist_ok=True)
    with FileLock(str(cached) + ".lock"):
        if not cached.is_dir():
            tmp = Path(tempfile.mkdtemp(prefix=".run-", dir=CACHE))
            shutil.copy(params, tmp / "params.yaml")
            subprocess.run(command(tmp / "params.yaml", tmp / "research"), cwd=tmp, env=env(),
                           check=True, capture_output=True)
            (tmp / "research").rename(tmp / "done")
            (tmp / "done").rename(cached)
            shutil.rmtree(tmp)
    shutil.copytree(cached, folder / "research")
    return params, folder / "research"
