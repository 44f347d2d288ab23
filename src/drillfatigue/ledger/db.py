"""Opening a ledger: the back-end from ``--db``, the schema version, transactions.

``--db`` is a file path (SQLite, the default back-end) or a SQLAlchemy URL
(``postgresql+psycopg://user@host/dbname``, ``sqlite:///path``). SQLite files
run in WAL mode (set when the ledger is created) with foreign keys on and
full synchronous commits, so a
process killed at any point leaves a consistent file; every write transaction
starts with ``BEGIN IMMEDIATE`` (it takes the write lock first, so two writers
wait for each other instead of failing on a lock upgrade). PostgreSQL runs
at its default READ COMMITTED level: the ingest's compare-and-set on the
run's chunk counter and the unique keys do the serialising.

The schema is versioned by Alembic (``alembic_version``); a ledger at an
older revision is refused with a one-line message naming
``drillfatigue ledger migrate``, which upgrades it explicitly. A database
that holds tables but no ledger revision is never touched.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from typing import TYPE_CHECKING

from sqlalchemy import Connection, Engine, create_engine, event, inspect, text
from sqlalchemy.engine import make_url
from sqlalchemy.exc import ArgumentError, OperationalError

from drillfatigue.errors import InputError

if TYPE_CHECKING:
    from alembic.config import Config

#: The newest schema revision (the head of ``migrations/versions``; a test checks it).
#: Opening a ledger compares with it without importing Alembic, which only
#: ``init`` and ``migrate`` need.
HEAD_REVISION = "0002"
MIGRATIONS_DIR = Path(__file__).resolve().parent / "migrations"
#: how long a SQLite writer waits for another writer's transaction, ms
SQLITE_BUSY_TIMEOUT_MS = 60_000
_WRITE = "ledger_write"


def database_url(db: str) -> str:
    """A SQLAlchemy URL for ``--db``: URLs pass through, a path becomes ``sqlite:///PATH``."""
    text = str(db).strip()
    if not text:
        raise InputError("--db", "empty", "a SQLite file path or a database URL")
    if "://" in text:
        try:
            url = make_url(text)
        except ArgumentError:
            raise InputError("--db", f"not a database URL: {text!r}",
                             "sqlite:///PATH or postgresql+psycopg://USER@HOST/DB") from None
        if url.get_backend_name() not in ("sqlite", "postgresql"):
            raise InputError("--db", f"back-end {url.get_backend_name()!r}",
                             "sqlite or postgresql")
        return text
    return f"sqlite:///{Path(text).resolve()}"


def _sqlite_events(engine: Engine) -> None:
    @event.listens_for(engine, "connect")
    def _on_connect(dbapi_conn: Any, _record: Any) -> None:
        # pysqlite's own BEGIN handling is switched off: the "begin" hook below
        # chooses DEFERRED (readers) or IMMEDIATE (writers)
        dbapi_conn.isolation_level = None
        cur = dbapi_conn.cursor()
        cur.execute(f"PRAGMA busy_timeout = {SQLITE_BUSY_TIMEOUT_MS}")
        cur.execute("PRAGMA foreign_keys = ON")
        cur.execute("PRAGMA synchronous = FULL")
        cur.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn: Connection) -> None:
        mode = "IMMEDIATE" if conn.get_execution_options().get(_WRITE) else "DEFERRED"
        conn.exec_driver_sql(f"BEGIN {mode}")


def alembic_config(conn: Connection) -> Config:
    """Alembic's configuration for the packaged migrations, bound to ``conn``."""
    # start-up: Alembic only to create or migrate a ledger
    from alembic.config import Config

    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS_DIR))
    cfg.attributes["connection"] = conn
    return cfg


def script_revisions() -> tuple[str | None, set[str]]:
    """The head and every revision of the packaged migration scripts (imports Alembic)."""
    # start-up: Alembic only to create or migrate a ledger
    from alembic.script import ScriptDirectory

    script = ScriptDirectory(str(MIGRATIONS_DIR))
    return script.get_current_head(), {r.revision for r in script.walk_revisions()}


class Ledger:
    """An open ledger: the engine and its transactions.

    Use :func:`open_ledger` (checks the schema revision) or :func:`init_ledger`.
    """

    def __init__(self, db: str) -> None:
        self.db = str(db)
        self.url = database_url(db)
        self.engine = create_engine(self.url, future=True, pool_pre_ping=True)
        self.dialect = self.engine.dialect.name
        if self.dialect == "sqlite":
            _sqlite_events(self.engine)

    @contextmanager
    def read(self) -> Iterator[Connection]:
        """A read transaction (a consistent snapshot on both back-ends)."""
        with self.engine.connect() as conn, conn.begin():
            yield conn

    @contextmanager
    def write(self) -> Iterator[Connection]:
        """A write transaction: committed on success, rolled back on any exception."""
        with self.engine.connect() as conn:
            conn = conn.execution_options(**{_WRITE: True})
            with conn.begin():
                yield conn

    def shown_name(self) -> str:
        """The ledger's file path, or its URL with the password hidden (for a page or a log)."""
        if self.dialect == "sqlite":
            return make_url(self.url).database or self.db
        return make_url(self.url).render_as_string(hide_password=True)

    def revision(self) -> str | None:
        """The schema revision of the database (None if it is not a ledger)."""
        with self.engine.connect() as conn:
            if "alembic_version" not in inspect(conn).get_table_names():
                return None
            rows = conn.execute(text("SELECT version_num FROM alembic_version")).fetchall()
            return str(rows[0][0]) if len(rows) == 1 else None

    def table_names(self) -> list[str]:
        with self.engine.connect() as conn:
            return list(inspect(conn).get_table_names())

    def dispose(self) -> None:
        self.engine.dispose()


def _reachable(ledger: Ledger) -> None:
    try:
        with ledger.engine.connect():
            pass
    except OperationalError as exc:
        first = str(exc.orig).strip().splitlines()[0] if exc.orig else str(exc)
        raise InputError("--db", f"cannot open {ledger.db!r}: {first}",
                         "a writable SQLite path or a reachable database URL") from None


def open_ledger(db: str) -> Ledger:
    """Open an existing ledger at the current schema revision.

    Raises
    ------
    InputError
        Not a ledger (run ``drillfatigue ledger init``), an older revision
        (run ``drillfatigue ledger migrate``) or a newer one.
    """
    if "://" not in str(db) and not Path(str(db)).is_file():
        raise InputError("--db", f"no ledger at {str(db)!r}",
                         f"an existing ledger (create it: drillfatigue ledger init --db {db})")
    ledger = Ledger(db)
    _reachable(ledger)
    rev = ledger.revision()
    head = HEAD_REVISION
    if rev == head:
        return ledger
    ledger.dispose()
    if rev is None:
        raise InputError("--db", f"{str(db)!r} is not a drillfatigue ledger",
                         f"a ledger (create one: drillfatigue ledger init --db {db})")
    if rev not in script_revisions()[1]:
        raise InputError("--db", f"ledger schema revision {rev} is newer than this "
                         f"drillfatigue knows ({head})", "upgrade drillfatigue")
    raise InputError("--db", f"ledger schema revision {rev} is older than this drillfatigue's "
                     f"{head}", f"migrate it first: drillfatigue ledger migrate --db {db}")


def init_ledger(db: str, revision: str = "head") -> tuple[Ledger, bool]:
    """Create the ledger's tables in an empty database; return it and whether it was created.

    An existing ledger at the current revision is left as it is (False). A
    database with other tables, or a ledger at another revision, is refused.
    The folder of a new SQLite file is created.
    """
    if "://" not in str(db):
        Path(str(db)).resolve().parent.mkdir(parents=True, exist_ok=True)
    ledger = Ledger(db)
    _reachable(ledger)
    rev = ledger.revision()
    if rev is not None:
        ledger.dispose()
        return open_ledger(db), False
    if ledger.table_names():
        ledger.dispose()
        raise InputError("--db", f"{str(db)!r} holds tables but no ledger",
                         "a new or empty database (the ledger never writes into others)")
    if ledger.dialect == "sqlite":
        # WAL is a property of the file, set once here (never on a file that is not a ledger)
        raw = ledger.engine.raw_connection()  # outside a transaction, as SQLite requires
        try:
            raw.driver_connection.execute("PRAGMA journal_mode = WAL")  # type: ignore[union-attr]
        finally:
            raw.close()
    # start-up: Alembic only to create or migrate a ledger
    from alembic import command

    with ledger.engine.begin() as conn:
        command.upgrade(alembic_config(conn), revision)
    return ledger, True


def migrate_ledger(db: str) -> tuple[str, str]:
    """Upgrade a ledger to the current revision; return (old, new) revisions."""
    if "://" not in str(db) and not Path(str(db)).is_file():
        raise InputError("--db", f"no ledger at {str(db)!r}", "an existing ledger")
    ledger = Ledger(db)
    _reachable(ledger)
    old = ledger.revision()
    if old is None:
        ledger.dispose()
        raise InputError("--db", f"{str(db)!r} is not a drillfatigue ledger",
                         f"a ledger (create one: drillfatigue ledger init --db {db})")
    # start-up: Alembic only to create or migrate a ledger
    from alembic import command

    with ledger.engine.begin() as conn:
        command.upgrade(alembic_config(conn), "head")
    ledger.dispose()
    return old, HEAD_REVISION
