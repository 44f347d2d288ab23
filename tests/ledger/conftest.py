"""Ledger fixtures: a throwaway PostgreSQL 15 server, a fresh ledger on each back-end.

The server is the system's PostgreSQL (``/usr/lib/postgresql/<v>/bin``,
``make postgres`` installs it): ``initdb`` into a temporary folder, listening
on a Unix socket in that folder only (no TCP port), stopped and deleted at
the end of the session. ``initdb`` refuses to run as root, so under root the
server runs as the ``postgres`` system user (``runuser``). The server's own
durability settings are relaxed (``fsync=off``): the tests kill clients,
never the server. In CI (``CI=true``) a server that cannot start fails the
PostgreSQL tests instead of skipping them.
"""

from __future__ import annotations

import glob
import os
import pwd
import shutil
import subprocess
import tempfile
import uuid
from collections.abc import Iterator
from pathlib import Path

import pytest

PG_USER = "postgres"


def _pg_bin() -> Path | None:
    for d in sorted(glob.glob("/usr/lib/postgresql/*/bin"), reverse=True):
        if Path(d, "initdb").is_file() and Path(d, "pg_ctl").is_file():
            return Path(d)
    found = shutil.which("initdb")
    return Path(found).parent if found else None


def _as_server_user(cmd: list[str]) -> list[str]:
    if os.geteuid() != 0:
        return cmd
    return ["runuser", "-u", PG_USER, "--", *cmd]


def _in_ci() -> bool:
    return os.environ.get("CI", "").lower() in ("1", "true", "yes")


class PgServer:
    """A running throwaway server; :meth:`new_database` gives a fresh database URL."""

    def __init__(self, bin_dir: Path, root: Path) -> None:
        self.bin_dir = bin_dir
        self.root = root
        self.data = root / "data"
        self.socket_dir = root

    def start(self) -> None:
        run = lambda cmd: subprocess.run(_as_server_user(cmd), check=True,  # noqa: E731
                                         capture_output=True, text=True, timeout=120)
        run([str(self.bin_dir / "initdb"), "-D", str(self.data), "-A", "trust", "-U", PG_USER,
             "--no-sync", "-E", "UTF8"])
        opts = (f"-c listen_addresses='' -c unix_socket_directories='{self.socket_dir}' "
                "-c fsync=off -c synchronous_commit=off -c full_page_writes=off "
                "-c max_connections=50")
        run([str(self.bin_dir / "pg_ctl"), "-D", str(self.data), "-o", opts, "-l",
             str(self.root / "server.log"), "-w", "-t", "60", "start"])

    def stop(self) -> None:
        subprocess.run(_as_server_user([str(self.bin_dir / "pg_ctl"), "-D", str(self.data),
                                        "-m", "immediate", "stop"]),
                       capture_output=True, timeout=60)

    def url(self, dbname: str) -> str:
        return f"postgresql+psycopg://{PG_USER}@/{dbname}?host={self.socket_dir}"

    def _admin(self, sql: str) -> None:
        import psycopg

        with psycopg.connect(host=str(self.socket_dir), user=PG_USER, dbname="postgres",
                             autocommit=True) as conn:
            conn.execute(sql)

    def new_database(self) -> str:
        name = f"ledger_{uuid.uuid4().hex[:12]}"
        self._admin(f'CREATE DATABASE "{name}"')
        return name

    def drop_database(self, name: str) -> None:
        self._admin(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


@pytest.fixture(scope="session")
def pg_server() -> Iterator[PgServer]:
    bin_dir = _pg_bin()
    problem = None
    server = None
    root = Path(tempfile.mkdtemp(prefix="ledger-pg-"))
    try:
        if bin_dir is None:
            problem = "no PostgreSQL server binaries (initdb, pg_ctl): run `make postgres`"
        else:
            if os.geteuid() == 0:
                ent = pwd.getpwnam(PG_USER)
                os.chown(root, ent.pw_uid, ent.pw_gid)
            root.chmod(0o700)
            server = PgServer(bin_dir, root)
            try:
                server.start()
            except (subprocess.CalledProcessError, OSError, KeyError) as exc:
                detail = getattr(exc, "stderr", "") or str(exc)
                problem = f"PostgreSQL did not start: {' '.join(str(detail).split())[:400]}"
                server = None
        if server is None:
            if _in_ci():
                pytest.fail(f"CI: {problem}")
            pytest.skip(problem or "PostgreSQL unavailable")
        yield server
    finally:
        if server is not None:
            server.stop()
        shutil.rmtree(root, ignore_errors=True)


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
