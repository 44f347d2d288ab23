"""``drillfatigue string show|import TALLY.csv``: a string tally in field units.

``show`` prints the components the tally defines (sizes from the catalogue of
:mod:`drillfatigue.io.catalogue` where the tally gives a description only);
``import`` writes them as a ``string`` section (YAML, SI) that a case or
params file can hold, so the pipeline runs the engineer's string.
"""

from __future__ import annotations

from pathlib import Path

import typer
import yaml
from rich.console import Console
from rich.table import Table

from drillfatigue.cli.app import app
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_write_text
from drillfatigue.io.display import Display, check_system
from drillfatigue.io.tally import load_tally
from drillfatigue.string.segments import build_segments
from drillfatigue.units import LB_PER_FT_KG_PER_M

string_app = typer.Typer(help="String tallies: show the components, import as a string section.",
                         no_args_is_help=True)
app.add_typer(string_app, name="string")

TallyArg = typer.Argument(..., help="tally CSV (rows from the bit up; see docs/field-data.md)")


@string_app.command("show")
def show(tally: Path = TallyArg,
         unit_system: str = typer.Option("si", "--units", help="si (m, mm, kg/m) or field "
                                         "(ft, in, lb/ft)")) -> None:
    """Print each component: type, length, OD/ID, tool joint, grade, mass per length."""
    d = Display(check_system(unit_system))
    t = load_tally(tally)
    lu, du = d.unit("length"), d.unit("diameter")
    wu = "lb/ft" if d.system == "field" else "kg/m"
    table = Table(title=f"string from {tally.name} (bit first)")
    for col in ("component", "type", f"length {lu}", f"OD {du}", f"ID {du}", f"TJ OD {du}",
                f"TJ ID {du}", "grade", f"mass {wu}", "segments"):
        table.add_column(col, justify="left" if col in ("component", "type", "grade")
                         else "right", no_wrap=True)
    seg_mass: dict[int, float] = {}
    seg = build_segments(t.string, 1000.0)  # mud density only sets buoyancy: unused here
    for i, ci in enumerate(seg.component_index):
        seg_mass.setdefault(int(ci), float(seg.mass_per_length_kg_per_m[i]))
    for i, c in enumerate(t.string.components):
        m = seg_mass[i] / (LB_PER_FT_KG_PER_M if d.system == "field" else 1.0)
        tj = [f"{d.value('diameter', v):.3f}" if v is not None else "-"
              for v in (c.tool_joint_od_m, c.tool_joint_id_m)]
        table.add_row(c.name or c.type, c.type, f"{d.value('length', c.length_m):.1f}",
                      f"{d.value('diameter', c.od_m):.3f}", f"{d.value('diameter', c.id_m):.3f}",
                      *tj, c.material.grade, f"{m:.1f}", str(c.n_segments))
    console = Console(width=max(Console().width, 120))
    console.print(table)
    console.print(f"total length {d.value('length', t.string.total_length_m):.1f} {lu}")
    if t.ignored_columns:
        console.print("columns not used: " + ", ".join(t.ignored_columns))


@string_app.command("import")
def import_(tally: Path = TallyArg,
            output: Path = typer.Option(..., "--out", "-o", help="YAML file to write "
                                        "(a string section)")) -> None:
    """Write the tally as a ``string:`` section (SI) for a case or params file."""
    if output.suffix.lower() not in (".yaml", ".yml"):
        raise InputError("--out", f"unsupported file type {output.suffix or '(none)'!r}",
                         ".yaml, .yml")
    parent = output.parent if str(output.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("--out", f"folder {str(parent)!r} does not exist", "an existing folder")
    t = load_tally(tally)
    data = {"string": t.string.model_dump(mode="json", exclude_none=True)}
    header = (f"# string section from the tally {tally.name} (drillfatigue string import);\n"
              "# components from the bit up, SI units.\n")
    atomic_write_text(output, header + yaml.safe_dump(data, sort_keys=False))
    typer.echo(f"wrote {output} ({len(t.string.components)} components, "
               f"{t.string.total_length_m:.1f} m)")
