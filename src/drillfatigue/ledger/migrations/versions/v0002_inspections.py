"""Inspections: date, method, RP 7G-2 class or DS-1 category, measured wall, OD, connection.

Revision ID: 0002
Revises: 0001
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "inspections",
        sa.Column("id", sa.Integer, autoincrement=True, nullable=False),
        sa.Column("joint_id", sa.Integer, nullable=False),
        sa.Column("inspected_on", sa.String(10), nullable=False),
        sa.Column("method", sa.String(32), nullable=False),
        sa.Column("standard", sa.String(16), nullable=False),
        sa.Column("result", sa.String(16), nullable=False),
        sa.Column("wall_m", sa.Float, nullable=True),
        sa.Column("od_m", sa.Float, nullable=True),
        sa.Column("connection_condition", sa.Text, nullable=True),
        sa.Column("damage_upper_at_record", sa.Float, nullable=False),
        sa.Column("recorded_at", sa.String(32), nullable=False),
        sa.PrimaryKeyConstraint("id", name="pk_inspections"),
        sa.ForeignKeyConstraint(["joint_id"], ["joints.id"],
                                name="fk_inspections_joint_id_joints"),
        sa.UniqueConstraint("joint_id", "inspected_on", "method",
                            name="uq_inspections_joint_day_method"),
    )


def downgrade() -> None:
    op.drop_table("inspections")
