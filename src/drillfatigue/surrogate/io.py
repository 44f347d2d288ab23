"""Atomic file writes (temp name in the same folder, then ``os.replace``)."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pandas as pd


def atomic_write(path: str | Path, write: Callable[[str], None]) -> Path:
    """Call ``write(tmp_path)`` then rename the temp file onto ``path``."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=p.suffix, dir=p.parent)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, p)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return p


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
