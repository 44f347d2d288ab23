"""``drillfatigue ledger ...``: every joint's fatigue life across runs, wells and trips.

    drillfatigue ledger init --db ledger.sqlite
    drillfatigue ledger run start RUN1 --well W-1 --tally tally.csv --survey survey.csv \\
        --model data/surrogate/model --set mu_static=0.35 ... --db ledger.sqlite
    drillfatigue ledger run list --db ledger.sqlite
    drillfatigue ledger ingest LOG.las --run RUN1 --db ledger.sqlite
    drillfatigue ledger follow LOG.csv --run RUN1 --every 10 --db ledger.sqlite
    drillfatigue ledger joints --units field --db ledger.sqlite
    drillfatigue ledger history DP-0042 --db ledger.sqlite
    drillfatigue ledger retire --retire-at 0.8 --inspect-at 0.5 --db ledger.sqlite
    drillfatigue ledger inspect DP-0042 --date 2026-03-20 --method UT --standard rp7g2 \\
        --result premium --db ledger.sqlite
    drillfatigue ledger export --out export/ --format csv --db ledger.sqlite

``--db`` is a SQLite file (default ``ledger.sqlite``) or a database URL
(``postgresql+psycopg://USER@HOST/DB``). See ``docs/ledger.md``.

``python -m drillfatigue.cli.ledger ARGS`` runs ``drillfatigue ledger ARGS``
with only this command group loaded (a shorter start for a process that a
rig computer restarts often).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd
import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import model_option, out_option
from drillfatigue.errors import InputError
from drillfatigue.io.display import Display, check_system

ledger_app = typer.Typer(help="Fatigue ledger: each joint's damage across runs, by serial.",
                         no_args_is_help=True)
run_app = typer.Typer(help="Register and end runs.", no_args_is_help=True)
serial_app = typer.Typer(help="Correct or swap serials (recorded with a reason).",
                         no_args_is_help=True)
ledger_app.add_typer(run_app, name="run")
ledger_app.add_typer(serial_app, name="serial")
app.add_typer(ledger_app, name="ledger")

DEFAULT_DB = "ledger.sqlite"
DbOpt = typer.Option(DEFAULT_DB, "--db", help="SQLite file or database URL "
                     "(postgresql+psycopg://USER@HOST/DB)")
RunOpt = typer.Option(..., "--run", help="run name (from `ledger run start`)")
UnitsOpt = typer.Option("si", "--units", help="units of lengths and diameters shown: si or field")
#: the columns of the retire and inspect lists printed by ``ledger retire``
RETIRE_SHOWN = ("serial", "component_type", "od_m", "damage", "damage_lower", "damage_upper",
                "remaining_life", "last_result", "reason")


def _print_table(df: pd.DataFrame) -> None:
    if df.empty:
        print("(none)")
        return
    with pd.option_context("display.max_rows", None, "display.max_columns", None,
                           "display.width", 200):
        print(df.to_string(index=False, float_format=lambda v: f"{v:.4g}"))


@ledger_app.command("init")
def init(db: str = DbOpt) -> None:
    """Create an empty ledger (a SQLite file, or the tables in an empty database)."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import init_ledger

    led, created = init_ledger(db)
    rev = led.revision()
    led.dispose()
    print(f"{'created' if created else 'already a ledger:'} {db} (schema revision {rev})")


@ledger_app.command("migrate")
def migrate(db: str = DbOpt) -> None:
    """Upgrade a ledger written by an older drillfatigue to this version's schema."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import migrate_ledger

    old, new = migrate_ledger(db)
    print(f"{db}: schema revision {old} -> {new}" if old != new
          else f"{db}: already at schema revision {new}")


def _parse_sets(items: list[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for it in items:
        if "=" not in it:
            raise InputError("--set", f"{it!r} is not NAME=VALUE", "NAME=VALUE")
        k, v = it.split("=", 1)
        k = k.strip().replace("-", "_")
        if k in out:
            raise InputError("--set", f"{k!r} given twice", "each name once")
        out[k] = v.strip()
    return out


@run_app.command("start")
def run_start(name: str = typer.Argument(..., help="run name, unique in the ledger"),
              tally: Path = typer.Option(..., "--tally", help="joint tally CSV, from the bit up, "
                                         "one row and serial per joint"),
              well: str = typer.Option(..., "--well-name", help="well name"),
              model: Path | None = model_option(None, help="surrogate model folder (the "
                                                "digital twin computes the damage)"),
              damage_function: str | None = typer.Option(
                  None, "--damage-function", help="MODULE:FUNCTION computing the damage instead "
                  "of a model (drillfatigue.ledger.standin:standin_increments to try the ledger "
                  "without one)"),
              survey: Path | None = typer.Option(None, "--survey", help="survey file (CSV in m "
                                                 "or ft, WITSML trajectory XML)"),
              settings: list[str] = typer.Option([], "--set", help="constant feature NAME=VALUE "
                                                 "for the twin (user units)"),
              db: str = DbOpt) -> None:
    """Register a run: its well, survey, tally (order from the bit up) and model."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import load_joint_tally, open_ledger, start_run
    from drillfatigue.ledger.twin_adapter import PYTHON_PREFIX, model_id

    if (model is None) == (damage_function is None):
        raise InputError("--model", "give exactly one of --model and --damage-function",
                         "--model FOLDER or --damage-function MODULE:FUNCTION")
    if model is not None:
        ref = str(model.resolve())
    else:
        ref = PYTHON_PREFIX + str(damage_function)
        # start-up: SQLAlchemy and the ledger load only when a ledger command runs
        from drillfatigue.ledger.ingest import damage_function_for

        damage_function_for(ref)  # importable now, not at the first ingest
    ident = model_id(ref)
    table = load_joint_tally(tally)
    survey_t = None
    if survey is not None:
        # start-up: SQLAlchemy and the ledger load only when a ledger command runs
        from drillfatigue.well.survey_file import twin_survey_table

        if not survey.is_file():
            raise InputError("--survey", f"file {str(survey)!r} not found", "an existing file")
        survey_t = twin_survey_table(survey)
    led = open_ledger(db)
    new = start_run(led, name, well, table, ref, ident, _parse_sets(list(settings)), survey_t)
    led.dispose()
    print(f"run {name} started in well {well}: {len(table)} joints from the bit up "
          f"({new} new to the ledger), {table['s_top_m'].iloc[-1]:.1f} m")


@run_app.command("end")
def run_end(name: str = typer.Argument(..., help="run name"), db: str = DbOpt) -> None:
    """End a run (pulled out of hole): no more log data is taken for it."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import end_run, open_ledger

    led = open_ledger(db)
    changed = end_run(led, name)
    led.dispose()
    print(f"run {name} ended" if changed else f"run {name} had ended already")


@run_app.command("list")
def run_list(db: str = DbOpt) -> None:
    """The runs, in the order started: well, open or ended, joints, chunks, log span, model."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import open_ledger, runs_table

    led = open_ledger(db)
    table = runs_table(led)
    led.dispose()
    _print_table(table.drop(columns=["model_id", "started_at", "ended_at"]))


@ledger_app.command("ingest")
def ingest(logs: list[Path] = typer.Argument(..., help="log files (LAS 2.0, WITSML 1.4.1.1 "
                                             "log XML, CSV), in time order"),
           run: str = RunOpt,
           chunk_rows: int = typer.Option(3600, "--chunk-rows", help="samples per transaction"),
           db: str = DbOpt) -> None:
    """Ingest a run's log, whole or in chunks; what was ingested before is not counted again."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import ingest_file, open_ledger
    from drillfatigue.ledger.ingest import read_log_file

    for p in logs:  # every file parses before anything is recorded
        read_log_file(p)
    led = open_ledger(db)
    for p in logs:
        ingest_file(led, run, p, chunk_rows, on_report=lambda r: print(r.line(), flush=True))
    led.dispose()


@ledger_app.command("follow")
def follow_cmd(source: Path = typer.Argument(..., help="a growing CSV/LAS log, or a folder "
                                             "receiving WITSML (or LAS/CSV) log chunks"),
               run: str = RunOpt,
               every: float = typer.Option(10.0, "--every", help="seconds between polls"),
               chunk_rows: int = typer.Option(60, "--chunk-rows", help="samples per "
                                              "transaction of a growing file"),
               max_polls: int | None = typer.Option(None, "--max-polls", help="stop after N "
                                                    "polls"),
               until_idle: int | None = typer.Option(None, "--until-idle", help="stop after N "
                                                     "polls in a row with nothing new"),
               db: str = DbOpt) -> None:
    """Ingest a log as it grows, every N s; a restart resumes where the ledger stands."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import follow, open_ledger

    led = open_ledger(db)
    summary = follow(led, run, source, every, chunk_rows, max_polls, until_idle,
                     on_report=lambda r: print(r.line(), flush=True),
                     on_refused=lambda line: print(f"refused {line}", file=sys.stderr,
                                                   flush=True))
    led.dispose()
    print(f"followed {source}: {summary.polls} poll(s), {summary.ingested} chunk(s) ingested"
          + (f", {len(summary.refused)} refused" if summary.refused else ""))
    if summary.refused:
        raise typer.Exit(2)


@ledger_app.command("joints")
def joints_cmd(units: str = UnitsOpt,
               out: Path | None = out_option(None, help="also write the table to this "
                                             "CSV file"),
               db: str = DbOpt) -> None:
    """The inventory: every joint by remaining life (least first), with intervals."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.files import atomic_output
    from drillfatigue.ledger import in_units, inventory, open_ledger

    check_system(units)
    if out is not None and out.suffix.lower() != ".csv":
        raise InputError("--out", f"{str(out)!r}", "a .csv file")
    led = open_ledger(db)
    table = in_units(inventory(led), units)
    led.dispose()
    _print_table(table)
    if out is not None:
        with atomic_output(out) as tmp:
            table.to_csv(tmp, index=False, lineterminator="\n")


@ledger_app.command("history")
def history_cmd(serial: str = typer.Argument(..., help="joint serial"), units: str = UnitsOpt,
                db: str = DbOpt) -> None:
    """One joint's history: its runs and positions, damage per run, serial events, inspections."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import history, in_units, open_ledger

    check_system(units)
    led = open_ledger(db)
    h = history(led, serial)
    led.dispose()
    print(f"{h.serial} ({h.component_type})")
    print("runs:")
    _print_table(in_units(h.runs, units))
    if not h.events.empty:
        print("serial events:")
        _print_table(h.events)
    print("inspections:")
    _print_table(in_units(h.inspections, units))


@ledger_app.command("retire")
def retire_cmd(retire_at: float = typer.Option(0.8, "--retire-at", help="retire when the "
                                               "damage reaches this fraction"),
               inspect_at: float = typer.Option(0.5, "--inspect-at", help="inspect when the "
                                                "upper bound of damage reaches this fraction"),
               reinspect_after: float = typer.Option(0.1, "--reinspect-after", help="inspect "
                                                     "again once the upper bound grew this much "
                                                     "since the last inspection"),
               downgraded_retire_at: float = typer.Option(0.5, "--downgraded-retire-at",
                                                          help="--retire-at for a joint last "
                                                          "inspected as RP 7G-2 class 2 or 3"),
               units: str = UnitsOpt, db: str = DbOpt) -> None:
    """Joints to retire and to inspect under the stated rules."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import RetireRules, in_units, open_ledger, retire_lists

    check_system(units)
    rules = RetireRules(retire_at=retire_at, inspect_at=inspect_at,
                        reinspect_after=reinspect_after,
                        downgraded_retire_at=downgraded_retire_at)
    led = open_ledger(db)
    lists = retire_lists(led, rules)
    led.dispose()
    for action in ("retire", "inspect"):
        part = lists[lists["action"] == action]
        print(f"{action} ({len(part)}):")
        _print_table(in_units(part[list(RETIRE_SHOWN)], units))


@ledger_app.command("inspect")
def inspect_cmd(serial: str = typer.Argument(..., help="joint serial"),
                date: str = typer.Option(..., "--date", help="inspection date YYYY-MM-DD"),
                method: str = typer.Option(..., "--method", help="method, e.g. UT, EMI, MPI, "
                                           "visual"),
                standard: str = typer.Option(..., "--standard", help="rp7g2 (API RP 7G-2 "
                                             "class) or ds1 (DS-1 category)"),
                result: str = typer.Option(..., "--result", help="rp7g2: new, premium, class2, "
                                           "class3, scrap; ds1: 1 to 5"),
                wall: float | None = typer.Option(None, "--wall", help="measured wall "
                                                  "(mm, or in with --units field)"),
                od: float | None = typer.Option(None, "--od", help="measured OD (mm, or in)"),
                connection: str | None = typer.Option(None, "--connection", help="connection "
                                                      "condition, free text"),
                units: str = UnitsOpt, db: str = DbOpt) -> None:
    """Record an inspection of a joint (written once per joint, date and method)."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import open_ledger, record_inspection

    display = Display(check_system(units))
    wall_m = None if wall is None else float(display.to_si("diameter", wall))
    od_m = None if od is None else float(display.to_si("diameter", od))
    led = open_ledger(db)
    new = record_inspection(led, serial, date, method, standard, result, wall_m, od_m, connection)
    led.dispose()
    print(f"{serial}: {'recorded' if new else 'already recorded:'} {date} {method} "
          f"{standard} {result}")


@serial_app.command("correct")
def serial_correct(old: str = typer.Argument(..., help="the serial recorded"),
                   new: str = typer.Argument(..., help="the right serial"),
                   reason: str = typer.Option(..., "--reason", help="why"),
                   db: str = DbOpt) -> None:
    """Correct a joint's serial; its history stays with it and the event is recorded."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import correct_serial, open_ledger

    led = open_ledger(db)
    correct_serial(led, old, new, reason)
    led.dispose()
    print(f"{old} -> {new} ({reason})")


@serial_app.command("swap")
def serial_swap(a: str = typer.Argument(..., help="one serial"),
                b: str = typer.Argument(..., help="the other serial"),
                reason: str = typer.Option(..., "--reason", help="why"),
                db: str = DbOpt) -> None:
    """Two joints' tags were swapped: each joint takes the other's serial."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import open_ledger, swap_serials

    led = open_ledger(db)
    swap_serials(led, a, b, reason)
    led.dispose()
    print(f"{a} <-> {b} ({reason})")


@ledger_app.command("export")
def export_cmd(out: Path = out_option(..., help="output folder"),
               fmt: str = typer.Option("csv", "--format", help="csv or parquet"),
               db: str = DbOpt) -> None:
    """Export the ledger's tables (natural keys, fixed row order: comparable byte for byte)."""
    # start-up: SQLAlchemy and the ledger load only when a ledger command runs
    from drillfatigue.ledger import export_ledger, open_ledger

    led = open_ledger(db)
    written = export_ledger(led, out, fmt)
    led.dispose()
    print(f"wrote {len(written)} tables to {out}/")


if __name__ == "__main__":
    from drillfatigue.cli import main

    # this module, run as __main__, has registered the group on the shared app already
    sys.exit(main(["ledger", *sys.argv[1:]], modules=()))
