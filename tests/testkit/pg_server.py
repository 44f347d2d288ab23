"""A throwaway PostgreSQL server from the system's packages, for the ledger's tests and benchmark.

``initdb`` into a temporary folder, listening on a Unix socket in that folder
only (no TCP port). ``initdb`` refuses to run as root, so under root the
server runs as the ``postgres`` system user (``runuser``). The server's own
durability settings are relaxed (``fsync=off``): the tests kill clients,
never the server.
"""

from __future__ import annotations

import glob
import os
import pwd
import shutil
import subprocess
import tempfile
import uuid
from pathlib import Path

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


def start_server() -> tuple[PgServer | None, str | None, Path]:
    """Start a server in a new temporary folder: (server, None, folder) or (None, why, folder)."""
    root = Path(tempfile.mkdtemp(prefix="ledger-pg-"))
    bin_dir = _pg_bin()
    if bin_dir is None:
        return None, "no PostgreSQL server binaries (initdb, pg_ctl): run `make postgres`", root
    try:
        if os.geteuid() == 0:
            ent = pwd.getpwnam(PG_USER)
            os.chown(root, ent.pw_uid, ent.pw_gid)
        root.chmod(0o700)
        server = PgServer(bin_dir, root)
        server.start()
    except (subprocess.CalledProcessError, OSError, KeyError) as exc:
        detail = getattr(exc, "stderr", "") or str(exc)
        return None, f"PostgreSQL did not start: {' '.join(str(detail).split())[:400]}", root
    return server, None, root


def stop_server(server: PgServer | None, root: Path) -> None:
    if server is not None:
        server.stop()
    shutil.rmtree(root, ignore_errors=True)
