"""DVC stage ``train``: fit the surrogate (deep ensemble + conformal + OOD) on the dataset.

Reads the ``surrogate`` section of ``params.yaml`` and the damage table
(``data/dataset/damage.parquet``, one row per case and component location);
writes the model folder (``data/surrogate/model/``: weights, metadata, OOD
reference, TorchScript export) and the dvclive training curves (per member
train/val loss per epoch, ``data/surrogate/training/``).

Usage: ``python pipeline/train.py [--params params.yaml] [--data data/dataset/damage.parquet]
[--out data/surrogate/model] [--live data/surrogate/training] [--synthetic-cases N]``
(``--synthetic-cases``: train on the documented synthetic table instead, for smoke tests.)
"""

from __future__ import annotations

import sys
from argparse import Namespace

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import Params  # noqa: E402
from drillfatigue.stage import Option, stage_main  # noqa: E402


OPTIONS = (Option("--data", default="data/dataset/damage.parquet"),
           Option("--out", default="data/surrogate/model"),
           Option("--live", default="data/surrogate/training"),
           Option("--synthetic-cases", type=int, default=0))


def train(params: Params, args: Namespace) -> str:
    from drillfatigue.files import OutputFolder
    from drillfatigue.surrogate import fit_surrogate, make_synthetic_dataset
    from drillfatigue.surrogate.bounds import domain_bounds
    from drillfatigue.surrogate.data import read_dataset
    from drillfatigue.surrogate.facade import MODEL_KIND

    cfg = params.surrogate
    OutputFolder.check(args.out, MODEL_KIND, "--out")  # before minutes of training
    frame = (make_synthetic_dataset(args.synthetic_cases, seed=cfg.split_seed)
             if args.synthetic_cases > 0 else read_dataset(args.data))
    # the sweep's design bounds the domain the model answers (the synthetic
    # table has its own ranges: bounded by its rows)
    bounds = (domain_bounds(params, cfg.features, frame["s_from_bit_m"].to_numpy())
              if args.synthetic_cases == 0 else None)
    model = fit_surrogate(frame, cfg, live_dir=args.live, bounds=bounds)
    model.save(args.out, option="--out")
    t = model.metadata["training"]
    return (f"trained {len(cfg.seeds)} members on {t['n_train_rows']} rows "
            f"({t['epochs']} epochs); conformal q = {model.conformal_quantile:.3f}; "
            f"saved {args.out}")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, train, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
