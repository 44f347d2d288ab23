"""``operation`` section of params.yaml (initial minimal model; extended by its owner)."""

from __future__ import annotations

from drillfatigue.config.base import StrictModel


class OperationConfig(StrictModel):
    """Settings of the ``operation`` section. Units: SI unless the field name says otherwise."""
