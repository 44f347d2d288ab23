"""The models a service answers with, loaded once and swapped atomically on reload.

A request takes the current :class:`LoadedModel` once, at its start, and uses
that object to the end: a reload builds and warms the new model beside the
old one and then replaces the entry in one assignment, so a request in flight
finishes on the model it started with and no request waits for a load or
sees a half-loaded model. A model folder rewritten in place by the train
stage (``Surrogate.save`` renames the whole folder) is picked up by a reload.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.surrogate import Surrogate
from drillfatigue.io.names import Vocabulary

#: rows of the warm-up batches: above the surrogate's single-pass size (256 rows), so
#: the TorchScript batch path is built and run
_WARM_ROWS = 512


@dataclass(frozen=True)
class LoadedModel:
    """One loaded model: never changed after it is built."""

    name: str
    path: Path
    surrogate: Surrogate
    vocab: Vocabulary
    generation: int
    loaded_at_utc: str


def _warm_up(sur: Surrogate) -> None:
    """One single-row and two batch predictions at the domain centre.

    The TorchScript batch network runs its first two calls unoptimised
    (:meth:`Surrogate.batch_module`); doing them here keeps that cost out of
    the first requests.
    """
    centre = 0.5 * (np.asarray(sur.domain.min_) + np.asarray(sur.domain.max_))
    x = np.tile(centre, (_WARM_ROWS, 1))
    c = np.zeros((_WARM_ROWS, len(sur.categorical)), dtype=np.int64)
    sur.predict_array(x[:1], c[:1])
    for _ in range(2):
        sur.predict_array(x, c, knn=False)


def parse_model_spec(spec: str) -> tuple[str, Path]:
    """``'NAME=PATH'`` or ``'PATH'`` (name: the folder's name) -> (name, path)."""
    if "=" in spec:
        name, path = spec.split("=", 1)
        name = name.strip()
    else:
        path = spec
        name = Path(spec).resolve().name
    if not name or not all(c.isalnum() or c in "_-." for c in name):
        raise InputError("--model", f"bad model name {name!r}", "letters, digits, _ - .")
    return name, Path(path)


class ModelRegistry:
    """Named surrogate models; the first is the default.

    Parameters
    ----------
    paths : mapping of str to path
        ``{name: model folder}``, at least one.

    Raises
    ------
    InputError
        No model, or a folder that is not a model folder.
    """

    def __init__(self, paths: Mapping[str, str | Path]) -> None:
        if not paths:
            raise InputError("--model", "no model given", "one or more model folders")
        self._paths = {name: Path(p) for name, p in paths.items()}
        self._reload_lock = threading.Lock()
        self._models: dict[str, LoadedModel] = {}
        for name in self._paths:
            self._models[name] = self._load(name, 1)
        self.default = next(iter(self._paths))

    def _load(self, name: str, generation: int) -> LoadedModel:
        path = self._paths[name]
        if not (path / "metadata.json").is_file():
            raise InputError("--model", f"{str(path)!r} is not a surrogate model folder",
                             "a folder written by the train stage")
        sur = Surrogate.load(path)
        _warm_up(sur)
        return LoadedModel(name=name, path=path, surrogate=sur,
                           vocab=Vocabulary(sur.features, sur.categorical),
                           generation=generation,
                           loaded_at_utc=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))

    @property
    def names(self) -> list[str]:
        return list(self._paths)

    def get(self, name: str | None = None, field: str = "model") -> LoadedModel:
        """The current model called ``name`` (default: the first)."""
        key = self.default if name is None else name
        models = self._models  # one read: a concurrent reload swaps the whole dict
        if key not in models:
            raise InputError(field, f"unknown model {key!r}", ", ".join(self._paths))
        return models[key]

    def all(self) -> list[LoadedModel]:
        models = self._models
        return [models[n] for n in self._paths]

    def reload(self, name: str | None = None, field: str = "model") -> list[LoadedModel]:
        """Reload ``name`` (default: every model) from its folder and swap it in.

        Requests keep being answered by the old model while the new one
        loads; a failed load leaves the old model in place and raises.
        """
        names = self.names if name is None else [name]
        for n in names:
            if n not in self._paths:
                raise InputError(field, f"unknown model {n!r}", ", ".join(self._paths))
        with self._reload_lock:
            fresh = [self._load(n, self._models[n].generation + 1) for n in names]
            swapped = dict(self._models)
            for m in fresh:
                swapped[m.name] = m
            self._models = swapped
        return fresh
