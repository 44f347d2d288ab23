"""Run the fenced commands of a Markdown document as written (docs are tests).

A document's ```` ```bash ```` blocks run in order in one scratch folder that
holds links to the repository's inputs (:data:`INPUTS`), so a block may use
what an earlier block of the same document wrote. A block may be preceded by a
marker comment ``<!-- readme-test: MARK (reason) -->``:

* ``skip``: not run (the make targets, a research-scale run, a server that runs
  until stopped); the reason in parentheses is required;
* ``needs-model``: a small surrogate with ``params.yaml``'s inputs
  (:func:`testkit.tiny_surrogate.train_tiny_surrogate`) stands at
  ``data/surrogate/model``, where ``make repro`` puts the trained one;
* ``needs-server``: as ``needs-model``, and ``drillfatigue serve`` answers on
  ``localhost:8000`` while the block runs.

docs/ledger.md and docs/dataset.md have tests of their own (:data:`OWN_TESTS`); the
ledger's knows one more
marker, ``needs-ledger-server``: ``drillfatigue serve --ledger
runs/ledger.sqlite`` (the ledger its earlier blocks wrote) answers on
``localhost:8000`` while the block runs (:func:`start_server`).

Blocks of other languages (``yaml``, ``text``, output shown in a document) are
not commands. README.md's Python block also runs (tests/pipeline/test_readme.py).
"""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from testkit.tiny_surrogate import train_tiny_surrogate

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"(?:<!-- readme-test: (?P<mark>[a-z-]+)(?P<why>[^>]*)-->\n)?"
                   r"```(?P<lang>\w*)\n(?P<code>.*?)```", re.S)
#: Repository inputs a document's commands may read (linked into the scratch folder).
INPUTS = ("params.yaml", "data/cases", "data/examples", "data/plans", "data/wells/inputs",
          "benchmarks")
MARKS = {"", "skip", "needs-model", "needs-server"}
SHELL = {"bash", "sh", "shell"}
SERVER_PORT = 8000


@dataclass(frozen=True)
class Block:
    """One fenced block: its marker, the marker's reason, the language and the code."""

    mark: str
    why: str
    lang: str
    code: str


def blocks(path: Path) -> list[Block]:
    """The fenced blocks of the Markdown file ``path``, in order."""
    text = path.read_text(encoding="utf-8")
    return [Block(m["mark"] or "", (m["why"] or "").strip(), m["lang"], m["code"])
            for m in FENCE.finditer(text)]


#: Documents whose commands a test of their own runs and checks the output of.
OWN_TESTS = {"docs/ledger.md": "tests/pipeline/test_ledger_docs.py",
             "docs/dataset.md": "tests/pipeline/test_dataset_docs.py"}


def documents() -> list[Path]:
    """The documents whose commands are tested here: docs/*.md and data/examples/*.md but
    :data:`OWN_TESTS`."""
    found = [*(ROOT / "docs").glob("*.md"), *(ROOT / "data" / "examples").glob("*.md")]
    return sorted(p for p in found if p.relative_to(ROOT).as_posix() not in OWN_TESTS)


def scratch(tmp: Path) -> dict[str, str]:
    """Link the inputs into ``tmp``; the environment that runs the repository's code."""
    for rel in INPUTS:
        (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp / rel).symlink_to(ROOT / rel)
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"),
                                                      env.get("PYTHONPATH")]))
    return env


def _port_open(port: int) -> bool:
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


def start_server(tmp: Path, env: dict[str, str],
                 serve_args: tuple[str, ...] = ("--model", "data/surrogate/model")
                 ) -> subprocess.Popen:
    """``drillfatigue serve SERVE_ARGS`` in ``tmp`` on ``localhost:8000``, once it answers."""
    if _port_open(SERVER_PORT):
        raise RuntimeError(f"port {SERVER_PORT} is taken: the documented curl needs it")
    proc = subprocess.Popen(["drillfatigue", "serve", *serve_args,
                             "--port", str(SERVER_PORT)], cwd=tmp, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60.0
    while not _port_open(SERVER_PORT):
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            raise RuntimeError("drillfatigue serve did not start: "
                               + (proc.stderr.read().decode()[-2000:] if proc.stderr else ""))
        time.sleep(0.2)
    return proc


def run_document(path: Path, tmp: Path) -> int:
    """Run every shell block of ``path`` in ``tmp``; the number run. AssertionError on
    a failed block (with its code and the end of its stderr)."""
    env = scratch(tmp)
    model_ready = False
    n = 0
    for i, b in enumerate(blocks(path)):
        if b.lang not in SHELL:
            continue
        assert b.mark in MARKS, f"{path.name} block {i}: unknown marker {b.mark!r}"
        if b.mark == "skip":
            assert b.why.startswith("(") and len(b.why) > 4, \
                f"{path.name} block {i}: a skipped block says why: readme-test: skip (reason)"
            continue
        if b.mark in ("needs-model", "needs-server") and not model_ready:
            train_tiny_surrogate(ROOT / "params.yaml", tmp / "data" / "surrogate" / "model")
            model_ready = True
        server = start_server(tmp, env) if b.mark == "needs-server" else None
        try:
            out = subprocess.run(["bash", "-euo", "pipefail", "-c", b.code], cwd=tmp, env=env,
                                 capture_output=True, text=True, timeout=600)
        finally:
            if server is not None:
                server.kill()
                server.wait()
        assert out.returncode == 0, (f"{path.relative_to(ROOT)} block {i} failed:\n{b.code}\n"
                                     f"{out.stdout[-1500:]}\n{out.stderr[-3000:]}")
        n += 1
    return n
