"""Refusals of the service that are not invalid input: a part it does not serve, a record
the path names that does not exist.

Both are answered like an :class:`~drillfatigue.errors.InputError`, with a JSON
body whose ``detail`` is one line ``field: problem (allowed: ...)``, but with
their own status: 503 for a part this server was not started with (a model,
a ledger), 404 for a record named in the path (a joint's serial).
"""

from __future__ import annotations

from drillfatigue.errors import OneLineMessage


class ServiceRefusal(OneLineMessage):
    """A one-line refusal with an HTTP status (see the module docstring)."""

    status = 400



class NotServed(ServiceRefusal):
    """The server was started without the part a request needs (503)."""

    status = 503


class NotFound(ServiceRefusal):
    """The record a request names in its path does not exist (404)."""

    status = 404
