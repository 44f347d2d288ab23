"""Error types shared by the whole package.

Bad user input raises :class:`InputError` (a ``ValueError``) naming the field
path, what is wrong and the allowed range. The CLI prints it as one line
``error: <field path>: <what is wrong> (allowed: ...)`` and exits with code 2.
A numba kernel never raises: it returns a code of :mod:`drillfatigue.status`,
which its Python wrapper turns into an exception (:func:`raise_for_status`).
"""

from __future__ import annotations

from drillfatigue.status import MESSAGES, OK


class OneLineMessage(Exception):
    """Base of the package's refusals: ``field: problem (allowed: ...)`` on one line."""

    field: str
    problem: str
    allowed: str | None

    def __init__(self, field: str, problem: str, allowed: str | None = None) -> None:
        self.field = field
        self.problem = problem
        self.allowed = allowed
        super().__init__(self.one_line())

    def one_line(self) -> str:
        text = f"{self.field}: {self.problem}"
        if self.allowed:
            text += f" (allowed: {self.allowed})"
        return " ".join(text.split())


class InputError(OneLineMessage, ValueError):
    """Invalid user input: a config field, a file, a query.

    Parameters
    ----------
    field : str
        Dotted path of the offending field (``string.components[0].od_m``) or
        a file name.
    problem : str
        What is wrong, e.g. ``"must be > 0, got -1.0"``.
    allowed : str, optional
        The allowed values or range, e.g. ``"0 < od_m <= 1.0"``.
    """



class Interrupted(Exception):
    """A command stopped by Ctrl-C; the message says what was left and how to go on.

    The CLI prints it as one line ``error: interrupted: <message>`` and exits
    with code 130.
    """


class SimulationError(RuntimeError):
    """A simulation diverged or failed; the message says when, where and why."""


class KernelError(RuntimeError):
    """A numba kernel returned a failure code: a capacity its wrapper sized too
    small, or a bug; not bad input. The message names the kernel and the code."""


def raise_for_status(status: int, kernel: str) -> None:
    """Raise :class:`KernelError` for a failure code of :mod:`drillfatigue.status`.

    Nothing happens for ``OK``. The message is ``"<kernel>: <what failed>
    (status <code>)"``, the text from :data:`drillfatigue.status.MESSAGES`. The
    simulator's codes go through :func:`drillfatigue.dynamics.run.model.raise_for_status`
    instead, which adds the time and the segment of the failure.
    """
    if status == OK:
        return
    raise KernelError(f"{kernel}: {MESSAGES.get(status, 'unknown status code')} (status {status})")
