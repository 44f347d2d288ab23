"""Ledger fixtures: a throwaway PostgreSQL server (:mod:`testkit.pg_server`), a fresh
ledger on each back-end, the ledger's commands run in this process.

In CI (``CI=true``) a server that cannot start fails the PostgreSQL tests
instead of skipping them.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from testkit.pg_server import PgServer, start_server, stop_server

from drillfatigue.cli import main


def _in_ci() -> bool:
    return os.environ.get("CI", "").lower() in ("1", "true", "yes")


@pytest.fixture(scope="session")
def pg_server() -> Iterator[PgServer]:
    server, problem, root = start_server()
    try:
        if server is None:
            if _in_ci():
                pytest.fail(f"CI: {problem}")
            pytest.skip(problem or "PostgreSQL unavailable")
        yield server
    finally:
        stop_server(server, root)


@pytest.fixture(params=["sqlite", "postgresql"])
def db_url(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    """A ``--db`` value for a new, empty ledger on each back-end."""
    if request.param == "sqlite":
        yield str(tmp_path / "ledger.sqlite")
        return
    server: PgServer = request.getfixturevalue("pg_server")
    name = server.new_database()
    try:
        yield server.url(name)
    finally:
        server.drop_database(name)


@pytest.fixture
def new_db(request: pytest.FixtureRequest, tmp_path: Path, db_url: str):  # noqa: ANN201
    """A factory of further empty ledgers on the same back-end as ``db_url``."""
    made: list[str] = []
    count = [0]

    def make() -> str:
        count[0] += 1
        if "://" not in db_url:
            return str(tmp_path / f"ledger{count[0] + 1}.sqlite")
        server: PgServer = request.getfixturevalue("pg_server")
        name = server.new_database()
        made.append(name)
        return server.url(name)

    yield make
    if made:
        server = request.getfixturevalue("pg_server")
        for name in made:
            server.drop_database(name)


class CliResult:
    def __init__(self, returncode: int, stdout: str, stderr: str) -> None:
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


@pytest.fixture
def run_cli(capsys: pytest.CaptureFixture[str]):  # noqa: ANN201
    """``drillfatigue ledger ARGS`` in this process (the kill tests start real processes)."""
    def call(*args: str) -> CliResult:
        capsys.readouterr()
        rc = main(["ledger", *args])
        out = capsys.readouterr()
        return CliResult(rc, out.out, out.err)
    return call
