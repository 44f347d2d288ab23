"""Joints, serial events, runs and their tallies, chunks, damage increments and totals.

Revision ID: 0001
Revises:
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "joints",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("serial", sa.String(64), nullable=False),
        sa.Column("component_type", sa.String(32), nullable=False),
        sa.Column("description", sa.String(200), nullable=False, server_default=""),
        sa.Column("od_m", sa.Float, nullable=True),
        sa.Column("id_m", sa.Float, nullable=True),
        sa.Column("length_m", sa.Float, nullable=True),
        sa.Column("grade", sa.String(16), nullable=True),
        sa.Column("connection", sa.String(32), nullable=True),
        sa.PrimaryKeyConstraint("id", name="pk_joints"),
        sa.UniqueConstraint("serial", name="uq_joints_serial"),
    )
    op.create_table(
        "serial_events",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("joint_id", sa.Integer, nullable=False),
        sa.Column("kind", sa.String(16), nullable=False),
        sa.Column("old_serial", sa.String(64), nullable=False),
        sa.Column("new_serial", sa.String(64), nullable=False),
        sa.Column("reason", sa.Text, nullable=False),
        sa.Column("recorded_at", sa.String(32), nullable=False),
        sa.PrimaryKeyConstraint("id", name="pk_serial_events"),
        sa.ForeignKeyConstraint(["joint_id"], ["joints.id"],
                                name="fk_serial_events_joint_id_joints"),
    )
    op.create_table(
        "runs",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("name", sa.String(64), nullable=False),
        sa.Column("well", sa.String(128), nullable=False),
        sa.Column("survey_json", sa.Text, nullable=True),
        sa.Column("model_ref", sa.Text, nullable=False),
        sa.Column("model_id", sa.String(64), nullable=False),
        sa.Column("constants_json", sa.Text, nullable=False),
        sa.Column("status", sa.String(8), nullable=False),
        sa.Column("started_at", sa.String(32), nullable=False),
        sa.Column("ended_at", sa.String(32), nullable=True),
        sa.Column("first_t_s", sa.Float, nullable=True),
        sa.Column("last_t_s", sa.Float, nullable=True),
        sa.Column("last_sample_json", sa.Text, nullable=True),
        sa.Column("chunk_seq", sa.Integer, nullable=False),
        sa.PrimaryKeyConstraint("id", name="pk_runs"),
        sa.UniqueConstraint("name", name="uq_runs_name"),
    )
    op.create_table(
        "run_items",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("run_id", sa.Integer, nullable=False),
        sa.Column("position", sa.Integer, nullable=False),
        sa.Column("joint_id", sa.Integer, nullable=False),
        sa.Column("length_m", sa.Float, nullable=False),
        sa.Column("s_bottom_m", sa.Float, nullable=False),
        sa.Column("s_top_m", sa.Float, nullable=False),
        sa.PrimaryKeyConstraint("id", name="pk_run_items"),
        sa.ForeignKeyConstraint(["run_id"], ["runs.id"], name="fk_run_items_run_id_runs"),
        sa.ForeignKeyConstraint(["joint_id"], ["joints.id"], name="fk_run_items_joint_id_joints"),
        sa.UniqueConstraint("run_id", "position", name="uq_run_items_run_position"),
        sa.UniqueConstraint("run_id", "joint_id", name="uq_run_items_run_joint"),
    )
    op.create_table(
        "chunks",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("run_id", sa.Integer, nullable=False),
        sa.Column("seq", sa.Integer, nullable=False),
        sa.Column("source", sa.Text, nullable=False),
        sa.Column("content_sha256", sa.String(64), nullable=False),
        sa.Column("t_first_s", sa.Float, nullable=False),
        sa.Column("t_last_s", sa.Float, nullable=False),
        sa.Column("counted_from_s", sa.Float, nullable=False),
        sa.Column("n_rows", sa.Integer, nullable=False),
        sa.Column("n_new_rows", sa.Integer, nullable=False),
        sa.Column("ingested_at", sa.String(32), nullable=False),
        sa.PrimaryKeyConstraint("id", name="pk_chunks"),
        sa.ForeignKeyConstraint(["run_id"], ["runs.id"], name="fk_chunks_run_id_runs"),
        sa.UniqueConstraint("run_id", "seq", name="uq_chunks_run_seq"),
        sa.UniqueConstraint("run_id", "content_sha256", name="uq_chunks_run_hash"),
    )
    op.create_table(
        "damage_increments",
        sa.Column("chunk_id", sa.Integer, nullable=False),
        sa.Column("joint_id", sa.Integer, nullable=False),
        sa.Column("location", sa.String(16), nullable=False),
        sa.Column("covered", sa.Boolean, nullable=False),
        sa.Column("not_covered_reason", sa.Text, nullable=True),
        sa.Column("damage", sa.Float, nullable=True),
        sa.Column("damage_lower", sa.Float, nullable=True),
        sa.Column("damage_upper", sa.Float, nullable=True),
        sa.Column("time_in_hole_s", sa.Float, nullable=False),
        sa.Column("revolutions", sa.Float, nullable=False),
        sa.Column("ood_time_s", sa.Float, nullable=False),
        sa.PrimaryKeyConstraint("chunk_id", "joint_id", "location", name="pk_damage_increments"),
        sa.ForeignKeyConstraint(["chunk_id"], ["chunks.id"],
                                name="fk_damage_increments_chunk_id_chunks"),
        sa.ForeignKeyConstraint(["joint_id"], ["joints.id"],
                                name="fk_damage_increments_joint_id_joints"),
    )
    op.create_table(
        "damage_totals",
        sa.Column("joint_id", sa.Integer, nullable=False),
        sa.Column("location", sa.String(16), nullable=False),
        sa.Column("damage", sa.Float, nullable=False),
        sa.Column("damage_lower", sa.Float, nullable=False),
        sa.Column("damage_upper", sa.Float, nullable=False),
        sa.Column("time_in_hole_s", sa.Float, nullable=False),
        sa.Column("revolutions", sa.Float, nullable=False),
        sa.Column("ood_time_s", sa.Float, nullable=False),
        sa.Column("not_covered_time_s", sa.Float, nullable=False),
        sa.Column("not_covered_reason", sa.Text, nullable=True),
        sa.PrimaryKeyConstraint("joint_id", "location", name="pk_damage_totals"),
        sa.ForeignKeyConstraint(["joint_id"], ["joints.id"],
                                name="fk_damage_totals_joint_id_joints"),
    )


def downgrade() -> None:
    for name in ("damage_totals", "damage_increments", "chunks", "run_items", "runs",
                 "serial_events", "joints"):
        op.drop_table(name)
