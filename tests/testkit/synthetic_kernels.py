"""CPU-bound numba kernel of the synthetic sweep case (benchmarks and tests only)."""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def burn(n: int, x0: float) -> float:  # pragma: no cover - compiled
    """Logistic-map loop of ``n`` iterations from ``x0`` in (0, 1); returns the mean iterate.

    Deterministic busy work with no physical meaning: it keeps one core busy
    for a time proportional to ``n`` (about 2-5 ns per iteration).
    """
    x = x0
    acc = 0.0
    for _ in range(n):
        x = 3.9 * x * (1.0 - x)
        acc += x
    return acc / max(n, 1)
