"""Alembic migrations of the ledger schema (run by :mod:`drillfatigue.ledger.db`)."""
