"""``drillfatigue serve``: the digital twin as an HTTP service with a web page.

:func:`create_app` builds the FastAPI application over a
:class:`ModelRegistry` of loaded surrogate models and, optionally, an open
fatigue ledger; the endpoints are listed in :mod:`drillfatigue.service.app`
(the ledger's in :mod:`drillfatigue.service.ledger`), the request and
response models in :mod:`drillfatigue.service.schemas`, the operating-log
formats in :mod:`drillfatigue.service.logs`. Needs the ``service`` extra
(FastAPI, uvicorn, and the ledger's SQLAlchemy). User documentation:
``docs/service.md``, ``docs/ledger.md``.
"""

from __future__ import annotations

from drillfatigue.service.app import Limits, create_app
from drillfatigue.service.registry import LoadedModel, ModelRegistry, parse_model_spec

__all__ = ["Limits", "LoadedModel", "ModelRegistry", "create_app", "parse_model_spec"]
