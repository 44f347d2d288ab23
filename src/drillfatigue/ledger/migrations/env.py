"""Alembic environment: migrations run on the connection :mod:`drillfatigue.ledger.db` passes.

There is no ``alembic.ini``: :func:`drillfatigue.ledger.db.alembic_config` builds
the configuration and puts an open connection in ``config.attributes``.
"""

from __future__ import annotations

from alembic import context

from drillfatigue.ledger.schema import metadata

connection = context.config.attributes["connection"]
context.configure(connection=connection, target_metadata=metadata,
                  render_as_batch=connection.dialect.name == "sqlite")
with context.begin_transaction():
    context.run_migrations()
