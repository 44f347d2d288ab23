"""A tiny surrogate with the pipeline's feature set, trained in seconds.

Stands in for ``data/surrogate/model`` (a DVC output) where a test runs a
command that needs a trained model. The table draws every operating feature
of ``params.yaml``'s ``surrogate`` section uniformly over the sweep's ranges,
and places the component types and locations of the design's BHAs at the
distances from the bit they sit at there (:data:`_PLACES`), with a smooth
made-up log10 damage rate; the model is only as right as that.
"""

from __future__ import annotations

import hashlib
import shutil
import tempfile
from pathlib import Path
from typing import Any

from filelock import FileLock

import numpy as np
import pandas as pd

from drillfatigue.config import load_params
from drillfatigue.surrogate import fit_surrogate
from drillfatigue.surrogate.bounds import domain_bounds

_RANGES = {
    "operation.rpm": (60.0, 180.0),
    "operation.wob_N": (30000.0, 120000.0),
    "operation.lobe_amplitude_m": (0.0, 0.002),
    "operation.mud_density_kg_per_m3": (1000.0, 1600.0),
    "friction.mu_dynamic": (0.15, 0.4),
    "bit_md_m": (560.0, 760.0),
    "local_dls_deg_per_30m": (0.0, 9.0),
    "local_inc_deg": (0.0, 90.0),
    "local_max_dls_deg_per_30m": (0.0, 9.0),
    "bit_inc_deg": (0.0, 90.0),
    "bit_dls_deg_per_30m": (0.0, 9.0),
    "build_to_bit_deg_per_30m": (0.0, 9.0),
}
#: (component type, locations, distance from the bit low, high in m) as in the design's BHAs
_PLACES = (
    ("stabilizer", ("body", "connection"), 0.9, 22.0),
    ("mwd", ("body", "connection"), 2.0, 12.0),
    ("collar", ("body", "connection"), 4.0, 60.0),
    ("jar", ("body", "connection"), 50.0, 80.0),
    ("hwdp", ("body", "connection", "upset"), 60.0, 150.0),
    ("drill_pipe", ("body", "connection", "upset"), 60.0, 550.0),
)


def tiny_table(features: tuple[str, ...], n_cases: int = 40, seed: int = 0) -> pd.DataFrame:
    """Rows of ``n_cases`` cases x the component types and locations of :data:`_PLACES`."""
    rng = np.random.default_rng(seed)
    rows = []
    for case in range(n_cases):
        values = {f: rng.uniform(*_RANGES.get(f, (0.0, 1.0))) for f in features
                  if f not in ("md_m", "s_from_bit_m")}
        bit_md = rng.uniform(*_RANGES["bit_md_m"])
        for ctype, locs, s_lo, s_hi in _PLACES:
            for s in rng.uniform(s_lo, s_hi, 3):
                for loc in locs:
                    rows.append({"case_id": f"case{case:03d}", "component_type": ctype,
                                 "location": loc, **values, "s_from_bit_m": s,
                                 "md_m": bit_md - s})
    frame = pd.DataFrame(rows)
    log_rate = (-6.0 + 2.0 * frame.get("local_dls_deg_per_30m", 0.0) / 9.0
                + frame["location"].eq("connection") * 0.5 + rng.normal(0.0, 0.05, len(frame)))
    for crit in ("matake", "findley", "uniaxial", "api_rp7g"):
        frame[f"damage_rate_per_h_{crit}"] = 10.0 ** log_rate
    return frame


ROOT = Path(__file__).resolve().parents[2]
#: Fitted models, shared by the test processes of a run (and kept between runs): a
#: folder per :func:`_cache_key`, written whole under a lock.
CACHE = ROOT / ".pytest_cache" / "tiny_surrogate"


def _cache_key(params_path: Path) -> str:
    """Digest of what the fit reads: the params file, this file, the package's sources and
    the versions of the fitting libraries."""
    import sklearn
    import torch

    h = hashlib.sha256(Path(params_path).read_bytes())
    h.update(Path(__file__).read_bytes())
    for f in sorted((ROOT / "src" / "drillfatigue").rglob("*.py")):
        h.update(f.relative_to(ROOT).as_posix().encode() + f.read_bytes())
    h.update(f"{torch.__version__} {sklearn.__version__} {np.__version__}".encode())
    return h.hexdigest()[:20]


def train_tiny_surrogate(params_path: Path, out_dir: Path) -> Path:
    """The model of :func:`fit_tiny_surrogate` copied into ``out_dir``: fitted once per
    params file and source tree (:data:`CACHE`), so every test that needs a model does
    not pay the fit again."""
    cached = CACHE / _cache_key(params_path)
    CACHE.mkdir(parents=True, exist_ok=True)
    with FileLock(str(cached) + ".lock"):
        if not cached.is_dir():
            tmp = Path(tempfile.mkdtemp(prefix=".fit-", dir=CACHE))
            fit_tiny_surrogate(params_path, tmp / "model")
            (tmp / "model").rename(cached)
            shutil.rmtree(tmp)
    shutil.copytree(cached, out_dir)
    return out_dir


def fit_tiny_surrogate(params_path: Path, out_dir: Path) -> Path:
    """Fit 5 one-layer members for a few epochs on :func:`tiny_table`; save to ``out_dir``."""
    params = load_params(params_path)
    cfg = params.surrogate.model_copy(
        update={"hidden_layers": (8,), "max_epochs": 20, "patience": 5})
    table = tiny_table(tuple(cfg.features))
    # the domain from the design, as the train stage saves it
    bounds = domain_bounds(params, cfg.features, table["s_from_bit_m"].to_numpy())
    model = fit_surrogate(table, cfg, bounds=bounds)
    model.save(out_dir)
    return out_dir


def open_domain(sur: Any) -> Any:
    """``sur`` with a domain that admits every row of the combinations it was trained on.

    For tests of what is computed from the answers (a replay's bookkeeping, a ranking's
    order): what the domain refuses is tested in tests/unit/surrogate/test_domain.py.
    """
    d = sur.domain
    d.group_min_ = np.full_like(d.group_min_, -np.inf)
    d.group_max_ = np.full_like(d.group_max_, np.inf)
    d.group_threshold_ = np.full_like(d.group_threshold_, np.inf)
    return sur
