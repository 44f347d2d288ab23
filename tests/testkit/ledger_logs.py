"""Small logs, tallies and helpers for the ledger's tests (stand-in damage function)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue.ledger import export_tables

STANDIN = "drillfatigue.ledger.standin:standin_increments"
SRC = Path(__file__).resolve().parents[2] / "src"


def make_log(n: int, seed: int = 0, t0: float = 0.0, md0: float = 40.0,
             step_s: float = 5.0) -> pd.DataFrame:
    """``n`` samples every ``step_s`` s: bit going down from ``md0`` m, rpm and WOB varying
    (some rpm above the stand-in's 200 rpm domain edge)."""
    rng = np.random.default_rng(seed)
    t = t0 + step_s * np.arange(n)
    return pd.DataFrame({
        "time_s": t,
        "bit_md_m": md0 + 0.02 * np.arange(n),
        "rpm": np.round(rng.uniform(60.0, 220.0, n), 1),
        "wob_kN": np.round(rng.uniform(0.0, 150.0, n), 1),
    })


def write_log(path: Path, log: pd.DataFrame) -> Path:
    """A rig-style CSV (headers with units) of a :func:`make_log` table."""
    log.rename(columns={"time_s": "Time (s)", "bit_md_m": "Bit Depth (m)", "rpm": "RPM (rpm)",
                       "wob_kN": "WOB (kN)"}).to_csv(path, index=False, lineterminator="\n")
    return path


def write_tally(path: Path, serials: list[str]) -> Path:
    """A tally from the bit up: a bit, then collars (DC*) and drill pipe (the rest)."""
    lines = ["Serial,Type,Length (m)"]
    for s in serials:
        kind, length = (("bit", 0.5) if s.startswith("B") else ("dc", 9.0) if s.startswith("DC")
                        else ("dp", 9.5))
        lines.append(f"{s},{kind},{length}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def export_bytes(db: str) -> dict[str, bytes]:
    """Every exported table as CSV bytes (what ``ledger export`` writes)."""
    from drillfatigue.ledger import open_ledger

    led = open_ledger(db)
    try:
        return {name: df.to_csv(index=False, lineterminator="\n").encode()
                for name, df in export_tables(led).items()}
    finally:
        led.dispose()


def cli_env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(SRC), env.get("PYTHONPATH")]))
    return env


def ledger_cmd(*args: str) -> list[str]:
    """The command line of ``drillfatigue ledger ARGS`` (only the ledger group loaded)."""
    return [sys.executable, "-m", "drillfatigue.cli.ledger", *args]


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(ledger_cmd(*args), capture_output=True, text=True, env=cli_env(),
                          cwd=cwd, timeout=120)
