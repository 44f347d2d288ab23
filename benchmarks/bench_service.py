"""Load test of ``drillfatigue serve`` on the loopback: latency, throughput, failures.

A surrogate with the default architecture of ``params.yaml`` (5 members x
[64, 64], fitted for a few epochs on the synthetic table: speed does not
depend on how well it is trained) is served by a real ``drillfatigue serve``
process (uvicorn, one worker). ``--clients`` threads, each with its own
keep-alive HTTP connection, send ``--queries`` single-condition
``POST /v1/query`` requests in total, as fast as the answers come back, each
with a different condition drawn inside the training domain. Reported:
latency per request as the client sees it (p50, p90, p99, max), throughput
(requests per second over the wall time), the number of conditions the
domain check answers with "no answer" (422, a right answer at the domain's
edge: the draws are inside the ranges, the distance test may still refuse one)
and the number of failed requests (any other status, or a transport error),
which must be zero. The
clients run on the same machine as the server and share its cores, so the
numbers are a lower bound of what the server does for remote clients.

Usage: ``python benchmarks/bench_service.py [--quick] [--queries 20000] [--clients 8]``
-> ``benchmarks/results/service.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import threading
import time
from pathlib import Path

import httpx
import numpy as np

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.files import atomic_write_json
from drillfatigue.surrogate import fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.data import SYNTHETIC_POSITIONS

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from testkit.served import served  # noqa: E402

RESULT = Path(__file__).parent / "results" / "service.json"
CATEGORIES = {"component_type": ["collar", "drill_pipe", "hwdp", "stabilizer"],
              "location": ["body", "connection"],
              "profile": ["build_hold", "double_bend", "late_kickoff"]}


def _conditions(n: int, seed: int) -> list[dict[str, float | str]]:
    """``n`` single conditions in user units, inside the synthetic design ranges: each names
    a component at one of the synthetic string's positions (the domain is per component
    type and location)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        s_from_bit, ctype = SYNTHETIC_POSITIONS[int(rng.integers(len(SYNTHETIC_POSITIONS)))]
        kop = rng.uniform(400, 700)
        out.append({"rpm": rng.uniform(60, 180), "wob_kN": rng.uniform(40, 180),
                    "rop_m_per_h": rng.uniform(8, 70), "mu_static": rng.uniform(0.25, 0.45),
                    "mu_dynamic": rng.uniform(0.2, 0.3), "mud_density_sg": rng.uniform(1.1, 1.5),
                    "amplitude_mm": rng.uniform(0.6, 1.9), "lobes": int(rng.integers(1, 4)),
                    "kop_m": kop, "dls_deg_per_30m": rng.uniform(2.5, 7.5),
                    "md_m": kop + rng.uniform(700, 1100) - s_from_bit, "s_from_bit_m": s_from_bit,
                    "local_dls_deg_per_30m": 0.0,
                    **{k: str(rng.choice(v)) for k, v in CATEGORIES.items()},
                    "component_type": ctype})
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="2000 queries (smoke run)")
    ap.add_argument("--queries", type=int, default=20_000)
    ap.add_argument("--clients", type=int, default=8)
    ap.add_argument("--out", default=str(RESULT))
    args = ap.parse_args(argv)
    n_total = 2000 if args.quick else args.queries
    if n_total < args.clients or args.clients < 1:
        ap.error("--queries must be >= --clients >= 1")
    load_start = os.getloadavg()[0]
    cfg = SurrogateConfig(max_epochs=3, patience=3)
    t0 = time.perf_counter()
    model = fit_surrogate(make_synthetic_dataset(200, seed=0), cfg)
    fit_s = time.perf_counter() - t0
    with tempfile.TemporaryDirectory(prefix="bench_service_") as tmp:
        folder = Path(tmp) / "model"
        model.save(folder, export=False)
        with served(["--model", str(folder)]) as (url, _server):
            per_client = [n_total // args.clients + (i < n_total % args.clients)
                          for i in range(args.clients)]
            latencies = [np.empty(n) for n in per_client]
            failed = [0] * args.clients
            refused = [0] * args.clients
            errors: list[str] = []
            bodies = [[json.dumps({"rows": [c]}).encode() for c in _conditions(n, seed=i)]
                      for i, n in enumerate(per_client)]
            start = threading.Barrier(args.clients + 1)

            def client(i: int) -> None:
                headers = {"content-type": "application/json"}
                with httpx.Client(base_url=url, timeout=60.0) as c:
                    c.get("/healthz")  # open the connection before the clock starts
                    start.wait()
                    for k, body in enumerate(bodies[i]):
                        t = time.perf_counter()
                        try:
                            r = c.post("/v1/query", content=body, headers=headers)
                            no_answer = r.status_code == 422 and "no answer" in r.text
                            refused[i] += no_answer
                            ok = r.status_code == 200 or no_answer
                            if not ok and len(errors) < 5:
                                errors.append(r.text[:200])
                        except httpx.HTTPError as exc:
                            ok = False
                            if len(errors) < 5:
                                errors.append(repr(exc))
                        latencies[i][k] = time.perf_counter() - t
                        failed[i] += not ok

            threads = [threading.Thread(target=client, args=(i,)) for i in range(args.clients)]
            for t in threads:
                t.start()
            start.wait()
            t_start = time.perf_counter()
            for t in threads:
                t.join()
            wall = time.perf_counter() - t_start
    lat_ms = np.concatenate(latencies) * 1e3
    res = {
        "machine": {"cpu_count": os.cpu_count(), "python": platform.python_version(),
                    "load_avg_1min_start": load_start,
                    "load_avg_1min_end": os.getloadavg()[0]},
        "model": {"members": len(cfg.seeds), "hidden_layers": list(cfg.hidden_layers),
                  "n_numeric": len(model.features), "n_categorical": len(model.categorical),
                  "fit_s": fit_s},
        "server": "drillfatigue serve (uvicorn, 1 worker), loopback",
        "request": "POST /v1/query, one condition per request, keep-alive",
        "clients": args.clients,
        "queries": int(n_total),
        "wall_s": wall,
        "throughput_per_s": n_total / wall,
        "latency_ms": {"p50": float(np.percentile(lat_ms, 50)),
                       "p90": float(np.percentile(lat_ms, 90)),
                       "p99": float(np.percentile(lat_ms, 99)),
                       "max": float(lat_ms.max()), "mean": float(lat_ms.mean())},
        "refused_no_answer": int(sum(refused)),
        "failed": int(sum(failed)),
        "failure_examples": errors,
    }
    atomic_write_json(args.out, res)
    print(json.dumps({k: res[k] for k in ("queries", "clients", "wall_s", "throughput_per_s",
                                          "latency_ms", "refused_no_answer", "failed")},
                     indent=2))
    return 0 if res["failed"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
