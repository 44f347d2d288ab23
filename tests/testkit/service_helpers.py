"""Shared pieces of the service tests: tiny trained models and a loopback server."""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue.config.base import validate
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.studies.plan import CandidateFile, candidate_rows
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from testkit.served import free_port

# the synthetic model's inputs (tests/data/synthetic_twin/README.md), not data/examples
EXAMPLES = Path(__file__).resolve().parents[1] / "data" / "synthetic_twin"
TINY = SurrogateConfig(hidden_layers=(16,), max_epochs=6, patience=6, batch_size=128,
                       n_threads=1)
#: the constant inputs of the example log (data/examples/README.md)
CONSTANTS = {"mu_static": 0.35, "mu_dynamic": 0.28, "mud_density_sg": 1.25,
             "amplitude_mm": 1.0, "lobes": 3, "kop_m": 500, "dls_deg_per_30m": 5,
             "profile": "build_hold", "local_dls_deg_per_30m": 0.0}
#: one full condition of the synthetic model, user names
CONDITION = {"rpm": 120, "wob_kN": 80, "rop_m_per_h": 20, "md_m": 1400, "s_from_bit_m": 40,
             "component_type": "collar", "location": "connection", **CONSTANTS}
#: three case-2 profiles, five bit positions each: 15 plan cases
PLAN = {"candidates": {
    "profile_1": {"kind": "family_member", "member": 1, "kop_m": 350.0},
    "profile_2": {"kind": "family_member", "member": 2, "kop_m": 450.0},
    "profile_3": {"kind": "family_member", "member": 3, "kop_m": 350.0}},
    "surrogate_bit_positions": 5}
PLAN_FEATURES = ("md_m", "s_from_bit_m", "local_dls_deg_per_30m", "bit_inc_deg")


def synthetic_model(seed: int = 4) -> Surrogate:
    """A tiny ensemble on the synthetic dataset (a few seconds)."""
    return fit_surrogate(make_synthetic_dataset(30, seed=seed), TINY)


def plan_model() -> Surrogate:
    """A tiny ensemble trained on the plan query rows of :data:`PLAN` themselves.

    Target: an analytic log10 rate growing with the local dogleg and falling
    with the distance from the bit; the model only has to answer the plan
    query's columns, not to be accurate.
    """
    cset = validate(CandidateFile, PLAN, "candidates")
    parts = []
    for name in cset.candidates:
        q = candidate_rows(cset, name)
        q["case_id"] = [f"{name}_{b:.1f}" for b in q["bit_position_md_m"]]
        parts.append(q)
    df = pd.concat(parts, ignore_index=True)
    y = (-6.0 + 0.3 * df["local_dls_deg_per_30m"] - df["s_from_bit_m"] / 300.0
         + 0.5 * (df["location"] == "connection"))
    df["damage_rate_per_h_matake"] = 10.0 ** y
    cfg = TINY.model_copy(update={"features": PLAN_FEATURES,
                                  "categorical": ("component_type", "location")})
    return fit_surrogate(df, cfg)


@contextlib.contextmanager
def running_server(app: object) -> Iterator[str]:
    """Serve ``app`` with uvicorn on a free loopback port in a thread; yield its URL."""
    import uvicorn

    port = free_port()
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port,
                                           log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30.0
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            raise RuntimeError("the test server did not start")
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(timeout=10.0)


def assert_one_line(detail: str) -> None:
    assert isinstance(detail, str) and detail
    assert "\n" not in detail and "Traceback" not in detail, detail


def finite_close(a: object, b: object, rtol: float) -> bool:
    return bool(np.allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float),
                            rtol=rtol, atol=0.0))
