"""The ledger's tables: one schema for SQLite and PostgreSQL.

The Alembic migrations in ``drillfatigue/ledger/migrations/versions`` build
exactly these tables (a test compares a migrated database with this metadata).
Surrogate keys (``id``) are internal: they are never exported, because a
transaction killed mid-way consumes PostgreSQL sequence values and would make
two otherwise equal ledgers differ. Natural keys (serial, run name, chunk
sequence number, location) identify rows outside the database.

Tables
------
joints
    One row per physical joint: its current serial, component type, the
    dimensions and grade from the tally and the catalogue.
serial_events
    A corrected or swapped serial, with its reason: the only way a joint's
    serial changes (history stays with the joint).
runs
    A run in a well: survey, model, constants, and the ingest cursor (the
    last ingested sample's time and values, and the number of chunks).
run_items
    The tally of a run, from the bit up: which joint sat at which position.
chunks
    Every ingested log chunk: source, time range, content hash; unique per
    run by content hash and by sequence number.
damage_increments
    Per chunk x joint x location: damage with its interval, time in hole,
    revolutions, time out of the model's domain, or why it is not covered.
damage_totals
    Per joint x location: the running sums of the increments, updated in the
    transaction that records them.
inspections
    What the contractor recorded: date, method, RP 7G-2 class or DS-1
    category, measured wall, OD, connection condition.
"""

from __future__ import annotations

from sqlalchemy import (
    Boolean,
    Column,
    Float,
    ForeignKey,
    Integer,
    MetaData,
    String,
    Table,
    Text,
    UniqueConstraint,
)

#: Constraint names spelled out, the same on every back-end (migrations refer to them).
NAMING = {
    "ix": "ix_%(column_0_label)s",
    "uq": "uq_%(table_name)s_%(column_0_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s_%(referred_table_name)s",
    "pk": "pk_%(table_name)s",
}

metadata = MetaData(naming_convention=NAMING)

joints = Table(
    "joints", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("serial", String(64), nullable=False, unique=True),
    Column("component_type", String(32), nullable=False),
    Column("description", String(200), nullable=False, server_default=""),
    Column("od_m", Float, nullable=True),
    Column("id_m", Float, nullable=True),
    Column("length_m", Float, nullable=True),
    Column("grade", String(16), nullable=True),
    Column("connection", String(32), nullable=True),
)

serial_events = Table(
    "serial_events", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("joint_id", Integer, ForeignKey("joints.id"), nullable=False),
    Column("kind", String(16), nullable=False),
    Column("old_serial", String(64), nullable=False),
    Column("new_serial", String(64), nullable=False),
    Column("reason", Text, nullable=False),
    Column("recorded_at", String(32), nullable=False),
)

runs = Table(
    "runs", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("name", String(64), nullable=False, unique=True),
    Column("well", String(128), nullable=False),
    Column("survey_json", Text, nullable=True),
    Column("model_ref", Text, nullable=False),
    Column("model_id", String(64), nullable=False),
    Column("constants_json", Text, nullable=False),
    Column("status", String(8), nullable=False),
    Column("started_at", String(32), nullable=False),
    Column("ended_at", String(32), nullable=True),
    Column("first_t_s", Float, nullable=True),
    Column("last_t_s", Float, nullable=True),
    Column("last_sample_json", Text, nullable=True),
    Column("chunk_seq", Integer, nullable=False),
)

run_items = Table(
    "run_items", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("run_id", Integer, ForeignKey("runs.id"), nullable=False),
    Column("position", Integer, nullable=False),
    Column("joint_id", Integer, ForeignKey("joints.id"), nullable=False),
    Column("length_m", Float, nullable=False),
    Column("s_bottom_m", Float, nullable=False),
    Column("s_top_m", Float, nullable=False),
    UniqueConstraint("run_id", "position", name="uq_run_items_run_position"),
    UniqueConstraint("run_id", "joint_id", name="uq_run_items_run_joint"),
)

chunks = Table(
    "chunks", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("run_id", Integer, ForeignKey("runs.id"), nullable=False),
    Column("seq", Integer, nullable=False),
    Column("source", Text, nullable=False),
    Column("content_sha256", String(64), nullable=False),
    Column("t_first_s", Float, nullable=False),
    Column("t_last_s", Float, nullable=False),
    Column("counted_from_s", Float, nullable=False),
    Column("n_rows", Integer, nullable=False),
    Column("n_new_rows", Integer, nullable=False),
    Column("ingested_at", String(32), nullable=False),
    UniqueConstraint("run_id", "seq", name="uq_chunks_run_seq"),
    UniqueConstraint("run_id", "content_sha256", name="uq_chunks_run_hash"),
)

damage_increments = Table(
    "damage_increments", metadata,
    Column("chunk_id", Integer, ForeignKey("chunks.id"), primary_key=True),
    Column("joint_id", Integer, ForeignKey("joints.id"), primary_key=True),
    Column("location", String(16), primary_key=True),
    Column("covered", Boolean, nullable=False),
    Column("not_covered_reason", Text, nullable=True),
    Column("damage", Float, nullable=True),
    Column("damage_lower", Float, nullable=True),
    Column("damage_upper", Float, nullable=True),
    Column("time_in_hole_s", Float, nullable=False),
    Column("revolutions", Float, nullable=False),
    Column("ood_time_s", Float, nullable=False),
)

damage_totals = Table(
    "damage_totals", metadata,
    Column("joint_id", Integer, ForeignKey("joints.id"), primary_key=True),
    Column("location", String(16), primary_key=True),
    Column("damage", Float, nullable=False),
    Column("damage_lower", Float, nullable=False),
    Column("damage_upper", Float, nullable=False),
    Column("time_in_hole_s", Float, nullable=False),
    Column("revolutions", Float, nullable=False),
    Column("ood_time_s", Float, nullable=False),
    Column("not_covered_time_s", Float, nullable=False),
    Column("not_covered_reason", Text, nullable=True),
)

inspections = Table(
    "inspections", metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("joint_id", Integer, ForeignKey("joints.id"), nullable=False),
    Column("inspected_on", String(10), nullable=False),
    Column("method", String(32), nullable=False),
    Column("standard", String(16), nullable=False),
    Column("result", String(16), nullable=False),
    Column("wall_m", Float, nullable=True),
    Column("od_m", Float, nullable=True),
    Column("connection_condition", Text, nullable=True),
    Column("damage_upper_at_record", Float, nullable=False),
    Column("recorded_at", String(32), nullable=False),
    UniqueConstraint("joint_id", "inspected_on", "method", name="uq_inspections_joint_day_method"),
)
