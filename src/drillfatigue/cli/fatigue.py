"""``drillfatigue fatigue RUN_DIR --out FAT_DIR``: fatigue damage of a simulator run."""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.config import FatigueConfig, load_params, note_default_section, validate
from drillfatigue.config.base import read_yaml
from drillfatigue.errors import InputError
from drillfatigue.fatigue.critical_plane import CRITERIA
from drillfatigue.fatigue.run import FATIGUE_KIND, FILES, evaluate_run
from drillfatigue.files import OutputFolder


def _parse_joints(text: str | None) -> list[int] | None:
    if text is None:
        return None
    try:
        out = [int(x) for x in text.split(",") if x.strip() != ""]
    except ValueError:
        raise InputError("--joints", f"not a comma-separated list of integers: {text!r}",
                         "e.g. 3,5,7") from None
    if not out or min(out) < 0:
        raise InputError("--joints", f"needs joint numbers >= 0, got {text!r}", "e.g. 3,5,7")
    return out


def _config(run_dir: Path, params: Path | None) -> FatigueConfig:
    if params is not None:
        cfg = load_params(params).fatigue
        note = note_default_section(params, "fatigue")
        if note:
            print(note, file=sys.stderr)
        return cfg
    case = run_dir / "case.yaml"
    if case.is_file():  # the run's resolved case: use its fatigue section only
        return validate(FatigueConfig, read_yaml(case).get("fatigue") or {}, "fatigue")
    return FatigueConfig()


@app.command("fatigue")
def fatigue(
    run_dir: Path = typer.Argument(..., help="simulator run directory (loads.parquet, ...)"),
    out: Path = typer.Option(..., "--out", "-o", help="output folder for damage.parquet etc."),
    criterion: str | None = typer.Option(None, "--criterion", "-c",
                                         help="fatigue criterion: " + "|".join(CRITERIA)
                                         + " (default: fatigue.criterion)"),
    joints: str | None = typer.Option(None, "--joints", "-j", help="comma-separated joints"),
    params: Path | None = typer.Option(None, "--params", "-p",
                                       help="params.yaml whose fatigue section to use "
                                            "(default: RUN_DIR/case.yaml, else defaults)"),
) -> None:
    """Rainflow, S-N and critical-plane damage per joint and location of a run."""
    OutputFolder.check(out, FATIGUE_KIND, "--out", FILES)  # at once, not after minutes of work
    if criterion is not None and criterion not in CRITERIA:
        raise InputError("--criterion", f"unknown criterion {criterion!r}", ", ".join(CRITERIA))
    sel = _parse_joints(joints)
    cfg = _config(run_dir, params)
    df = evaluate_run(run_dir, cfg, out, joints=sel, criterion=criterion)
    g = df.loc[df["damage"].idxmax()]
    typer.echo(f"{len(df)} rows -> {out / 'damage.parquet'}; governing joint {int(g['joint'])} "
               f"{g['location']}: damage {g['damage']:.3e} per window, life {g['life_h']:.4g} h")
