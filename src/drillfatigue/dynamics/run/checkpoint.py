"""Checkpoint and resume: the state of a run saved between chunks, restored bit for bit.

``checkpoint.npz`` in the run folder (:mod:`drillfatigue.rundir`) holds the
integrator state (:class:`drillfatigue.dynamics.core.bundles.State`), the parts of
the model that change as the string grows (``seg``, ``jp``, ``topp``), the
rotation matrices ``R``, joint loads and channels of the last force
evaluation (the growth and rig steps read them before the next one) and a JSON
``meta`` record: the configuration hash, the number of the next history part and
the driver's running figures. Time is step x dt, so
a resumed run repeats exactly the arithmetic of an uninterrupted one.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from drillfatigue import rundir
from drillfatigue.dynamics.core.bundles import State
from drillfatigue.dynamics.run.model import Model
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output


def save_checkpoint(folder: OutputFolder, meta: dict[str, Any], model: Model,
                    state: State) -> None:
    """Write ``checkpoint.npz`` atomically (``meta`` must be JSON-ready)."""
    assert model.work is not None
    with atomic_output(folder.file(rundir.CHECKPOINT)) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, meta=np.array(json.dumps(meta)), R=model.work.R, loads=model.work.loads,
                 ch=model.work.ch, seg=model.seg, jp=model.jp, topp=model.topp,
                 **state.arrays())


def load_checkpoint(folder: OutputFolder, config_hash: str, model: Model,
                    state: State) -> dict[str, Any] | None:
    """Restore ``model`` and ``state`` in place from the folder's checkpoint; return its
    ``meta``, or None when there is none.

    Raises
    ------
    InputError
        The checkpoint belongs to another configuration.
    """
    path = folder.path / rundir.CHECKPOINT
    if not path.is_file():
        return None
    assert model.work is not None
    with np.load(path) as z:
        meta = json.loads(str(z["meta"]))
        if meta["hash"] != config_hash:
            raise InputError("--resume", "the checkpoint in the run directory belongs to a "
                             "different configuration", "the same case file as the run")
        for k, arr in state.arrays().items():
            arr[...] = z[k]
        model.work.R[...] = z["R"]
        # the rig boundaries' step reads the last force evaluation's loads and channels
        model.work.loads[...] = z["loads"]
        model.work.ch[...] = z["ch"]
        model.seg[...] = z["seg"]
        model.jp[...] = z["jp"]
        model.topp[...] = z["topp"]
    return meta
