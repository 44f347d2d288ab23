"""Every shell block of docs/ledger.md runs, in order, in a scratch copy of the inputs.

Blocks marked ``<!-- readme-test: skip (...) -->`` need the pipeline's model,
a PostgreSQL server, an older ledger or run until stopped; they are checked
for the marker only. A block marked ``needs-ledger-server`` runs while
``drillfatigue serve --ledger runs/ledger.sqlite`` answers on
``localhost:8000`` (:func:`testkit.doc_blocks.start_server`).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from testkit.doc_blocks import start_server

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"(?:<!-- readme-test: (?P<mark>[a-z-]+)[^>]*-->\n)?```(?P<lang>\w+)\n(?P<code>.*?)```",
                   re.S)


def blocks() -> list[tuple[str, str, str]]:
    text = (ROOT / "docs" / "ledger.md").read_text(encoding="utf-8")
    return [(m["mark"] or "", m["lang"], m["code"]) for m in FENCE.finditer(text)]


def test_the_guide_has_runnable_blocks() -> None:
    b = blocks()
    assert sum(mark == "" for mark, _, _ in b) >= 6
    assert {lang for _, lang, _ in b} == {"bash"}
    assert {m for m, _, _ in b} <= {"", "skip", "needs-ledger-server"}


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_every_ledger_guide_block_runs(tmp_path: Path) -> None:
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "examples").symlink_to(ROOT / "data" / "examples")
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    outputs = []
    for i, (mark, _lang, code) in enumerate(blocks()):
        if mark == "skip":
            continue
        server = (start_server(tmp_path, env, ("--ledger", "runs/ledger.sqlite"))
                  if mark == "needs-ledger-server" else None)
        try:
            out = subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=tmp_path,
                                 env=env, capture_output=True, text=True, timeout=300)
        finally:
            if server is not None:
                server.kill()
                server.wait()
        assert out.returncode == 0, f"block {i} failed:\n{code}\n{out.stderr[-3000:]}"
        outputs.append(out.stdout)
    # what the guide says the commands show
    text = "\n".join(outputs)
    assert text.count("already ingested as chunk") == 5
    totals = pd.read_csv(tmp_path / "runs" / "ledger_export" / "damage_totals.csv")
    assert (totals.groupby("serial")["time_in_hole_s"].max() > 0).all()
    assert "retire (" in text and "inspect (" in text
    # the service answers from the same ledger: field units, the lists, a history, and a
    # chunk the follow counted already is not counted again
    assert '"units":"field"' in text and '"length_ft"' in text
    assert '"retire":[{' in text and '"serial":"DC-1001"' in text
    assert '"status":"nothing new"' in text
