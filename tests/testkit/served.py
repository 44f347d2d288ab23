"""``drillfatigue serve`` as a user starts it: a real process on a free loopback port.

Shared by the service tests and the service benchmarks (``benchmarks/`` put ``tests/`` on
``sys.path``): start the command, wait for ``/healthz``, hand back its URL and process,
stop it on the way out.
"""

from __future__ import annotations

import contextlib
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Mapping, Sequence

import httpx


def free_port() -> int:
    """A loopback TCP port free now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def served(args: Sequence[str], *, start_s: float = 120.0,
           env: Mapping[str, str] | None = None
           ) -> Iterator[tuple[str, subprocess.Popen[str]]]:
    """Run ``drillfatigue serve *args --port P``; yield ``(url, process)`` once it answers
    ``/healthz``, then terminate it (kill after 30 s). The process's output (stdout and
    stderr together) stays readable after the block.

    Raises
    ------
    RuntimeError
        The server exited or did not answer within ``start_s`` (its output in the message).
    """
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    proc = subprocess.Popen([sys.executable, "-m", "drillfatigue", "serve", *args,
                             "--port", str(port)], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True,
                            env=None if env is None else dict(env))
    try:
        deadline = time.monotonic() + start_s
        while True:
            try:
                if httpx.get(url + "/healthz", timeout=2.0).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                proc.kill()
                out = proc.stdout.read() if proc.stdout else ""
                raise RuntimeError(f"server did not start: {out}")
            time.sleep(0.2)
        yield url, proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
