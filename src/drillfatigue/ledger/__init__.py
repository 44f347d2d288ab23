"""The fatigue ledger: every joint's damage across runs, wells and trips.

A SQLite file (the default) or a PostgreSQL database, one schema for both
(SQLAlchemy Core, Alembic migrations). Runs carry their tally from the bit
up; log chunks are ingested exactly once (:mod:`drillfatigue.ledger.ingest`)
and their damage, computed by the digital twin behind one adapter
(:mod:`drillfatigue.ledger.twin_adapter`), is added to each joint by its
serial. The query functions (:mod:`drillfatigue.ledger.queries`) answer the
inventory, a joint's history, the retire and inspect lists and the runs, for
the ``drillfatigue ledger`` commands and the service's ``/v1/ledger``
endpoints alike. See ``docs/ledger.md``.
"""

from drillfatigue.ledger.db import Ledger, init_ledger, migrate_ledger, open_ledger
from drillfatigue.ledger.follow import FollowSummary, follow
from drillfatigue.ledger.increments import DamageFunction, RunContext
from drillfatigue.ledger.ingest import (
    IngestReport,
    LogChunk,
    ingest_chunk,
    ingest_file,
    read_log_file,
)
from drillfatigue.ledger.queries import (
    JointHistory,
    RetireRules,
    export_ledger,
    export_tables,
    history,
    in_units,
    inventory,
    ledger_summary,
    retire_lists,
    runs_table,
)
from drillfatigue.ledger.store import (
    NotInLedger,
    correct_serial,
    end_run,
    record_inspection,
    start_run,
    swap_serials,
)
from drillfatigue.ledger.tally import load_joint_tally

__all__ = [
    "DamageFunction", "FollowSummary", "IngestReport", "JointHistory", "Ledger", "LogChunk",
    "NotInLedger", "RetireRules", "RunContext", "correct_serial", "end_run", "export_ledger",
    "export_tables", "follow", "history", "in_units", "ingest_chunk", "ingest_file",
    "init_ledger", "inventory", "ledger_summary", "load_joint_tally", "migrate_ledger",
    "open_ledger", "read_log_file", "record_inspection", "retire_lists", "runs_table",
    "start_run", "swap_serials",
]
