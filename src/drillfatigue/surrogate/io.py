"""Atomic writes of the surrogate's tables, JSON and figures (through
:func:`drillfatigue.files.atomic_output`)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pandas as pd

from drillfatigue.files import atomic_output


def atomic_write(path: str | Path, write: Callable[[str], None]) -> Path:
    """Call ``write(tmp_path)`` then rename the temp file onto ``path``."""
    with atomic_output(path) as tmp:
        write(str(tmp))
    return Path(path)


def write_csv(frame: pd.DataFrame, path: str | Path) -> Path:
    return atomic_write(path, lambda t: frame.to_csv(t, index=False))


def write_json(data: Any, path: str | Path) -> Path:
    def w(t: str) -> None:
        with open(t, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=2)
            f.write("\n")
    return atomic_write(path, w)


def save_figure(fig: Any, path: str | Path, dpi: int = 120) -> Path:
    fmt = Path(path).suffix.lstrip(".") or "png"
    return atomic_write(path, lambda t: fig.savefig(t, dpi=dpi, format=fmt))
