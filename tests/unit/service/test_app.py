"""The HTTP API of ``drillfatigue serve`` (FastAPI test client and a loopback server).

Every endpoint is checked against the library function it wraps (the CLI's
own outputs where the CLI has the command): the service adds transport, not
numbers. Every refused request must be a 4xx with a one-line ``detail``
naming the field and the allowed values, never a 500 or a traceback.
"""

from __future__ import annotations

import threading
import warnings
from pathlib import Path

import httpx
import numpy as np
import pandas as pd
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from drillfatigue.cli import main
from drillfatigue.config.base import validate
from drillfatigue.service import Limits, ModelRegistry, create_app
from drillfatigue.service import logs as service_logs
from drillfatigue.studies.plan import CandidateFile, predict_candidates
from drillfatigue.surrogate import Surrogate
from drillfatigue.surrogate.facade import PREDICTION_COLUMNS
from drillfatigue.surrogate.twin import replay_log

from testkit.service_helpers import (
    CONDITION,
    CONSTANTS,
    EXAMPLES,
    PLAN,
    assert_one_line,
    plan_model,
    running_server,
    synthetic_model,
)

with warnings.catch_warnings():
    # starlette asks for httpx2 in its test client; httpx is what is pinned
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")

# float32 network: the same rows predicted in two batches of different make-up
# differ by BLAS round-off, ~1e-7 in log10 (test_twin.py); 1e-5 relative in a
# rate or life bounds that with margin
RTOL = 1e-5


@pytest.fixture(scope="module")
def folders(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("models")
    synthetic_model().save(root / "synthetic", export=False)
    plan_model().save(root / "plan", export=False)
    return {"synthetic": root / "synthetic", "plan": root / "plan"}


@pytest.fixture(scope="module")
def registry(folders: dict[str, Path]) -> ModelRegistry:
    return ModelRegistry(folders)


@pytest.fixture(scope="module")
def client(registry: ModelRegistry) -> TestClient:
    return TestClient(create_app(registry, Limits(max_query_rows=50, max_log_rows=1000,
                                                  max_window_nodes=500)))


def _replay_body(**extra: object) -> dict:
    return {"log": {"format": "csv", "text": (EXAMPLES / "operating_log.csv").read_text()},
            "components_csv": (EXAMPLES / "components.csv").read_text(),
            "constants": CONSTANTS, **extra}


# -- health, models, schema -----------------------------------------------------------
def test_health_models_and_openapi(client: TestClient, registry: ModelRegistry) -> None:
    h = client.get("/healthz")
    assert h.status_code == 200 and h.json()["status"] == "ok"
    assert set(h.json()["models"]) == {"synthetic", "plan"}
    m = client.get("/v1/models").json()
    assert m["default"] == "synthetic" and [x["name"] for x in m["models"]] == ["synthetic",
                                                                               "plan"]
    docs = client.get("/docs")
    assert docs.status_code == 200 and "/static/vendor/swagger-ui-bundle.js" in docs.text
    assert "cdn" not in docs.text.lower()  # the machine may be offline: nothing external
    assert client.get("/static/vendor/swagger-ui-bundle.js").status_code == 200
    paths = client.get("/openapi.json").json()["paths"]
    for p in ("/healthz", "/v1/models", "/v1/model", "/v1/model/reload", "/v1/query",
              "/v1/twin/replay", "/v1/plan/rank", "/v1/window", "/v1/window.png"):
        assert p in paths, p
    # the request schemas are the pydantic models, incl. the CLI's config models
    schemas = client.get("/openapi.json").json()["components"]["schemas"]
    assert {"QueryRequest", "ReplayRequest", "StringConfig", "WellConfig",
            "CandidateFile"} <= set(schemas)


def test_model_card_has_domain_ranges_and_training(client: TestClient,
                                                   registry: ModelRegistry) -> None:
    card = client.get("/v1/model", params={"name": "synthetic"}).json()
    sur = registry.get("synthetic").surrogate
    assert [f["column"] for f in card["features"]] == sur.features
    assert [f["min"] for f in card["features"]] == sur.domain.min_.tolist()
    assert [f["max"] for f in card["features"]] == sur.domain.max_.tolist()
    wob = next(f for f in card["features"] if f["column"] == "operation.wob_N")
    assert {"wob_N", "wob_kN", "wob_klbf"} <= set(wob["names"])
    assert {f["column"]: f["levels"] for f in card["categorical"]} == sur.categories
    assert card["coverage"] == sur.coverage and card["criterion"] == "matake"
    assert card["training"]["n_train_rows"] == sur.metadata["training"]["n_train_rows"]
    assert sum(card["split"].values()) == 30  # 30 synthetic cases in the three parts
    assert "csv" in card["log_formats"] and card["limits"]["max_query_rows"] == 50
    r = client.get("/v1/model", params={"name": "nope"})
    assert r.status_code == 422 and r.json()["detail"].startswith("name: unknown model 'nope'")


# -- query ----------------------------------------------------------------------------
def test_query_equals_cli_batch_output(client: TestClient, folders: dict[str, Path],
                                       tmp_path: Path) -> None:
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(folders["synthetic"]), "--csv",
                 str(EXAMPLES / "conditions.csv"), "--out", str(out)]) == 0
    cli = pd.read_csv(out, keep_default_na=False)
    rows = pd.read_csv(EXAMPLES / "conditions.csv").to_dict(orient="records")
    r = client.post("/v1/query", json={"rows": rows})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["columns"] == list(cli.columns)
    assert body["columns"][-len(PREDICTION_COLUMNS):] == list(PREDICTION_COLUMNS)
    api = pd.DataFrame(body["rows"], columns=body["columns"])
    for col in PREDICTION_COLUMNS:
        if col in ("ood", "ood_reason", "beyond_horizon"):
            assert api[col].astype(str).tolist() == cli[col].astype(str).tolist()
        else:  # an out-of-domain row has no number: null in JSON, empty in the CSV
            np.testing.assert_allclose(api[col].astype(float),
                                       pd.to_numeric(cli[col].replace("", np.nan)), rtol=RTOL)


def test_query_single_row_and_unit_variants(client: TestClient,
                                            registry: ModelRegistry) -> None:
    sur = registry.get("synthetic").surrogate
    a = client.post("/v1/query", json={"rows": [CONDITION]}).json()["rows"][0]
    # the same condition in other units gives the same answer
    other = {k: v for k, v in CONDITION.items() if k not in ("wob_kN", "rop_m_per_h")}
    other.update(wob_klbf=80e3 / 4448.2216152605, rop_ft_per_h=20 / 0.3048)
    b = client.post("/v1/query", json={"rows": [other]}).json()["rows"][0]
    assert np.isclose(a["life_h"], b["life_h"], rtol=RTOL)
    frame = registry.get("synthetic").vocab.frame_from_mapping(CONDITION)
    ref = sur.predict(frame).iloc[0]
    assert np.isclose(a["damage_rate_per_h"], ref["damage_rate_per_h"], rtol=RTOL)
    assert a["ood"] == bool(ref["ood"])


def test_query_batch_limit_and_model_choice(client: TestClient) -> None:
    r = client.post("/v1/query", json={"rows": [CONDITION] * 51})
    assert r.status_code == 422
    assert r.json()["detail"] == "rows: 51 rows (allowed: at most 50)"
    r = client.post("/v1/query", json={"model": "plan", "rows": [CONDITION]})
    assert r.status_code == 422 and r.json()["detail"].startswith("rows.")
    r = client.post("/v1/query", json={"model": "zzz", "rows": [CONDITION]})
    assert r.json()["detail"] == "model: unknown model 'zzz' (allowed: synthetic, plan)"


# -- refused requests: one line, 4xx -----------------------------------------------------
BAD = [
    ("/v1/query", {"rows": []}, "rows"),
    ("/v1/query", {}, "rows"),
    ("/v1/query", {"rows": [CONDITION], "colour": 1}, "colour"),
    ("/v1/query", {"rows": [{**CONDITION, "rpm": "fast"}]}, "rows.rpm"),
    ("/v1/query", {"rows": [{**CONDITION, "rpm": None}]}, "rows"),
    ("/v1/query", {"rows": [{**CONDITION, "wob_lbs": 3}]}, "rows.wob_lbs"),
    ("/v1/query", {"rows": [{**CONDITION, "component_type": "reamer"}]},
     "rows.component_type: value 'reamer' not seen in training"),
    ("/v1/query", {"rows": [CONDITION, {"rpm": 100}]}, "rows[1]."),
    ("/v1/query", {"rows": "all of them"}, "rows"),
    ("/v1/query", [1, 2], "body"),
    ("/v1/twin/replay", _replay_body(log={"format": "xls", "text": "x"}), "log.format"),
    ("/v1/twin/replay", _replay_body(log={"format": "las", "text": "x"}), "log.text"),
    ("/v1/twin/replay", _replay_body(log={"format": "csv", "text": ""}), "log.text"),
    ("/v1/twin/replay", _replay_body(log={"format": "csv", "text": "time_s,bit_md_m\n5,1\n1,1"}),
     "time_s"),
    ("/v1/twin/replay", _replay_body(components=[{"serial": "a", "s_from_bit_m": 1}]),
     "components"),
    ("/v1/twin/replay", _replay_body(components_csv=None), "components"),
    ("/v1/twin/replay", _replay_body(components_csv="serial,s_from_bit_m\na,-3"),
     "components_csv.s_from_bit_m"),
    ("/v1/twin/replay", _replay_body(constants={}), "mu_static"),
    ("/v1/twin/replay", _replay_body(retire_at_damage=2), "retire_at_damage"),
    ("/v1/twin/replay", _replay_body(survey=[{"md_m": 0, "dls_deg_per_30m": 0}], well={}),
     "well"),
    ("/v1/twin/replay", _replay_body(string={"components": []}), "string.components"),
    ("/v1/plan/rank", {"model": "plan"}, "candidates"),
    ("/v1/plan/rank", {"model": "plan", "candidates_yaml": "candidates: [x"}, "candidates_yaml"),
    ("/v1/plan/rank", {"model": "plan", "candidates": {"candidates": {}}},
     "candidates.candidates"),
    ("/v1/plan/rank", {"model": "plan", "candidates": {**PLAN, "colour": 1}},
     "candidates.colour"),
    ("/v1/plan/rank", {"candidates": PLAN}, "surrogate"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200}, "fixed": {}}, "y"),
    ("/v1/window", {"x": {"name": "rpm", "start": 200, "stop": 40},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200}, "fixed": CONDITION}, "x"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200, "n": 1},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200}, "fixed": {}}, "x.n"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200},
                    "y": {"name": "location", "start": 0, "stop": 1}, "fixed": {}}, "y.name"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200},
                    "y": {"name": "rpm", "start": 0, "stop": 1}, "fixed": {}}, "y.name"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200, "n": 30},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200, "n": 30},
                    "fixed": {}}, "grid"),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200},
                    "fixed": {"md_m": 1000}}, "fixed."),
    ("/v1/window", {"x": {"name": "rpm", "start": 40, "stop": 200},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200},
                    "fixed": CONDITION}, "fixed.rpm"),
    ("/v1/model/reload", {"model": "other"}, "model"),
    # physical bounds (drillfatigue.limits), in a batch as in a single row; booleans
    ("/v1/query", {"rows": [{**CONDITION, "rpm": -5}]},
     "rows.rpm: -5 is outside the physical range (allowed: 0 <= rpm <= 1000)"),
    ("/v1/query", {"rows": [CONDITION, {**CONDITION, "rpm": -5}]},
     "rows[1].rpm: -5 is outside the physical range (allowed: 0 <= rpm <= 1000)"),
    ("/v1/query", {"rows": [CONDITION, {**CONDITION, "mud_density_sg": 4}]},
     "rows[1].mud_density_sg: 4 is outside the physical range (allowed: 0 <= mud_density_sg "
     "<= 3)"),
    ("/v1/query", {"rows": [{**CONDITION, "rpm": True}]},
     "rows[0].rpm: true is a JSON boolean, not a number (allowed: a number)"),
    ("/v1/twin/replay", _replay_body(constants={**CONSTANTS, "amplitude_mm": -1000.0}),
     "amplitude_mm: -1000 is outside the physical range (allowed: 0 <= amplitude_mm <= 50)"),
    ("/v1/twin/replay", _replay_body(constants={**CONSTANTS, "amplitude_mm": 5000.0}),
     "amplitude_mm: 5000 is outside the physical range"),
    ("/v1/twin/replay", _replay_body(constants={**CONSTANTS, "mu_static": False}),
     "constants.mu_static: false is a JSON boolean"),
    ("/v1/window", {"x": {"name": "rpm", "start": -10, "stop": 200},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200},
                    "fixed": {k: v for k, v in CONDITION.items() if k not in ("rpm", "wob_kN")}},
     "x.start: -10 is outside the physical range (allowed: 0 <= rpm <= 1000)"),
    ("/v1/twin/replay", _replay_body(
        components_csv="serial,s_from_bit_m,component_type,location\na,,collar,body"),
     "components_csv.s_from_bit_m: empty cell (row 1)"),
    ("/v1/twin/replay", _replay_body(log={"format": "csv",
                                          "text": "time_s,bit_md_m,rpm\n0,1,120\n60,2"}),
     "log.text: row 2 has 2 cells, the header 3"),
    ("/v1/window", {"x": {"name": "rpm", "start": True, "stop": 200},
                    "y": {"name": "wob_kN", "start": 20, "stop": 200}, "fixed": {}},
     "x.start: true is a JSON boolean"),
]


@pytest.mark.parametrize("path, body, field", BAD, ids=[f"{p}:{f}" for p, _, f in BAD])
def test_bad_request_is_422_one_line(client: TestClient, path: str, body: object,
                                     field: str) -> None:
    r = client.post(path, json=body)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert_one_line(detail)
    assert detail.startswith(field), detail
    assert "(allowed: " in detail, detail


def test_invalid_json_and_body_size_limits(registry: ModelRegistry) -> None:
    c = TestClient(create_app(registry, Limits(max_body_bytes=2000)))
    r = c.post("/v1/query", content=b'{"rows": [', headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"].startswith("body: invalid JSON")
    big = {"rows": [CONDITION] * 20}
    r = c.post("/v1/query", json=big)
    assert r.status_code == 413
    assert r.json()["detail"] == "body: over the size limit (allowed: at most 2000 bytes)"
    # a chunked body without a length is counted as it arrives
    payload = httpx.Request("POST", "http://x", json=big).content
    chunks = iter([payload[:1500], payload[1500:]])
    r = c.post("/v1/query", content=chunks, headers={"content-type": "application/json"})
    assert r.status_code == 413 and r.json()["detail"].startswith("body: over the size limit")
    assert c.post("/v1/query", json={"rows": [CONDITION]}).status_code == 200


def test_unexpected_failure_is_500_without_traceback(folders: dict[str, Path],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    reg = ModelRegistry({"synthetic": folders["synthetic"]})
    sur = reg.get().surrogate

    def broken(*args: object, **kwargs: object) -> dict:
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(sur, "predict_array", broken)
    r = TestClient(create_app(reg)).post("/v1/query", json={"rows": [CONDITION]})
    assert r.status_code == 500
    assert r.json()["detail"] == ("internal error (ZeroDivisionError); the server log has "
                                  "the details")
    assert "a bug" not in r.text and "Traceback" not in r.text


json_values = st.recursive(
    st.none() | st.booleans() | st.floats(allow_nan=False, allow_infinity=False)
    | st.integers() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner,
                                                                max_size=3), max_leaves=8)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(rows=st.lists(st.dictionaries(st.sampled_from(sorted(CONDITION) + ["x", "wob_N"]),
                                     json_values, max_size=4), max_size=3),
       extra=st.dictionaries(st.sampled_from(["rows", "model", "x"]), json_values, max_size=2))
def test_any_json_body_is_answered_200_or_one_line_422(client: TestClient, rows: list,
                                                       extra: dict) -> None:
    body = {"rows": rows, **extra}
    r = client.post("/v1/query", json=body)
    assert r.status_code in (200, 422), r.text
    if r.status_code == 422:
        assert_one_line(r.json()["detail"])


# -- twin replay ------------------------------------------------------------------------
def test_replay_equals_library_and_cli(client: TestClient, registry: ModelRegistry,
                                       folders: dict[str, Path], tmp_path: Path) -> None:
    r = client.post("/v1/twin/replay", json=_replay_body(retire_at_damage=1.0))
    assert r.status_code == 200, r.text
    body = r.json()
    comps = pd.read_csv(EXAMPLES / "components.csv")
    ref = replay_log(pd.read_csv(EXAMPLES / "operating_log.csv"), comps,
                     registry.get().surrogate, CONSTANTS).components
    api = pd.DataFrame(body["components"], columns=body["columns"])
    assert list(api["serial"]) == list(ref["serial"]) and body["n_locations"] == len(comps)
    for col in ("damage", "damage_lower", "damage_upper", "remaining_life_h"):
        np.testing.assert_allclose(api[col].astype(float), ref[col], rtol=RTOL)
    np.testing.assert_array_equal(api["ood_time_s"], ref["ood_time_s"])
    assert body["duration_h"] == pytest.approx(2.0)
    assert body["max_damage_serial"] == ref.loc[ref["damage"].idxmax(), "serial"]
    # the CLI writes the same table
    out = tmp_path / "twin"
    args = ["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model",
            str(folders["synthetic"]), "--components", str(EXAMPLES / "components.csv"),
            "--out", str(out)]
    for k, v in CONSTANTS.items():
        args += ["--set", f"{k}={v}"]
    assert main(args) == 0
    cli = pd.read_csv(out / "components_damage.csv")
    np.testing.assert_allclose(api["damage"].astype(float), cli["damage"], rtol=RTOL)
    # no component reaches damage 1 in 2 h of these conditions
    assert ref["damage_upper"].max() < 1.0 and body["retire"] == []


def _as_las(frame: pd.DataFrame) -> str:
    """The example log as LAS 2.0 text, time-indexed, mnemonics a rig would use."""
    head = ["~VERSION INFORMATION", " VERS. 2.0 : CWLS LOG ASCII STANDARD - VERSION 2.0",
            " WRAP. NO : ONE LINE PER STEP", "~WELL INFORMATION", " NULL. -999.25 : NULL",
            "~CURVE INFORMATION", " ETIM .s : elapsed time", " BITDEP .m : bit depth",
            " RPM .rpm : surface rpm", " SWOB .kN : weight on bit", " ROP .m/h : ROP", "~A"]
    rows = [" ".join(repr(float(v)) for v in r) for r in
            frame[["time_s", "bit_md_m", "rpm", "wob_kN", "rop_m_per_h"]].to_numpy()]
    return "\n".join(head + rows) + "\n"


def test_replay_of_a_las_log_equals_the_csv_log(client: TestClient) -> None:
    # the field-log readers of drillfatigue.io are plugged into the service
    log = pd.read_csv(EXAMPLES / "operating_log.csv")
    csv = client.post("/v1/twin/replay", json=_replay_body()).json()
    las = client.post("/v1/twin/replay",
                      json=_replay_body(log={"format": "las", "text": _as_las(log)}))
    assert las.status_code == 200, las.text
    a = pd.DataFrame(csv["components"], columns=csv["columns"])
    b = pd.DataFrame(las.json()["components"], columns=las.json()["columns"])
    np.testing.assert_allclose(b["damage"].astype(float), a["damage"].astype(float),
                               rtol=1e-12)
    assert "las" in client.get("/v1/model").json()["log_formats"]


def test_retire_list_applies_both_limits(client: TestClient) -> None:
    body = client.post("/v1/twin/replay", json=_replay_body()).json()
    comps = pd.DataFrame(body["components"], columns=body["columns"])
    limit = float(np.median(comps["damage_upper"]))
    hours = float(np.median(comps["remaining_life_h_lower"]))
    r = client.post("/v1/twin/replay", json=_replay_body(retire_at_damage=limit,
                                                          retire_within_h=hours)).json()
    want = comps[(comps["damage_upper"] >= limit) | (comps["remaining_life_h_lower"] < hours)]
    want = want.sort_values("damage", ascending=False, kind="stable")
    assert [e["serial"] for e in r["retire"]] == list(want["serial"])
    assert 0 < len(r["retire"]) < len(comps)
    assert all(e["reason"] for e in r["retire"])


def test_replay_log_reader_can_be_plugged_in(client: TestClient,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    # a reader for a made-up semicolon format: registered, then accepted by name
    def semicolon(data: bytes) -> pd.DataFrame:
        lines = data.decode().strip().splitlines()
        head = lines[0].split(";")
        return pd.DataFrame([[float(v) for v in ln.split(";")] for ln in lines[1:]],
                            columns=head)

    monkeypatch.setitem(service_logs._READERS, "semicolon", semicolon)
    text = (EXAMPLES / "operating_log.csv").read_text().replace(",", ";")
    a = client.post("/v1/twin/replay", json=_replay_body()).json()
    b = client.post("/v1/twin/replay",
                    json=_replay_body(log={"format": "semicolon", "text": text})).json()
    assert [c["damage"] for c in a["components"]] == [c["damage"] for c in b["components"]]
    assert "semicolon" in client.get("/v1/model").json()["log_formats"]


def test_replay_with_survey_rows_and_row_limit(client: TestClient) -> None:
    survey = pd.read_csv(EXAMPLES / "survey.csv").to_dict(orient="records")
    consts = {k: v for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"}
    r = client.post("/v1/twin/replay", json=_replay_body(constants=consts, survey=survey))
    assert r.status_code == 200, r.text
    r = client.post("/v1/twin/replay", json=_replay_body(survey=survey))
    assert r.status_code == 422 and "local_dls_deg_per_30m" in r.json()["detail"]
    rows = "time_s,bit_md_m,rpm,wob_kN,rop_m_per_h\n" + "".join(
        f"{i},1200,120,80,18\n" for i in range(1001))
    r = client.post("/v1/twin/replay", json=_replay_body(log={"format": "csv", "text": rows}))
    assert r.json()["detail"] == "log.text: 1001 rows (allowed: at most 1000)"


# -- plan ranking --------------------------------------------------------------------------
def test_plan_rank_equals_library_ranking(client: TestClient, registry: ModelRegistry) -> None:
    cset = validate(CandidateFile, PLAN, "candidates")
    ref = predict_candidates(cset, registry.get("plan").surrogate)
    ref = ref.sort_values("life_windows_surrogate", ascending=False, kind="stable")
    r = client.post("/v1/plan/rank", json={"model": "plan", "candidates": PLAN})
    assert r.status_code == 200, r.text
    body = r.json()
    assert [row["candidate"] for row in body["rows"]] == list(ref["candidate"])
    assert body["best"] == ref["candidate"].iloc[0]
    assert [row["rank_surrogate"] for row in body["rows"]] == [1, 2, 3]
    np.testing.assert_allclose([row["life_windows_surrogate"] for row in body["rows"]],
                               ref["life_windows_surrogate"], rtol=RTOL)
    # the YAML text of the same candidates gives the same answer
    y = client.post("/v1/plan/rank", json={"model": "plan",
                                           "candidates_yaml": yaml.safe_dump(PLAN)}).json()
    assert y["rows"] == body["rows"]


# -- window ------------------------------------------------------------------------------------
def test_window_endpoint_json_and_png(client: TestClient, registry: ModelRegistry) -> None:
    fixed = {k: v for k, v in CONDITION.items() if k not in ("rpm", "wob_kN")}
    req = {"x": {"name": "rpm", "start": 20, "stop": 220, "n": 11},
           "y": {"name": "wob_kN", "start": 20, "stop": 200, "n": 7}, "fixed": fixed}
    r = client.post("/v1/window", json=req)
    assert r.status_code == 200, r.text
    w = r.json()
    assert len(w["life_h"]) == 7 and len(w["life_h"][0]) == 11
    # node (i, j) is the plain query at (rpm_j, wob_i)
    sur = registry.get().surrogate
    i, j = 3, 4
    q = client.post("/v1/query", json={"rows": [{**fixed, "rpm": w["x"]["values"][j],
                                                 "wob_kN": w["y"]["values"][i]}]}).json()
    assert np.isclose(w["life_h"][i][j], q["rows"][0]["life_h"], rtol=RTOL)
    # rpm 20 and 220 lie outside the synthetic training range (40-200): hatched
    lo, hi = sur.domain.min_[0], sur.domain.max_[0]
    assert all(row[0] and row[-1] for row in w["ood"]) and 20 < lo and hi < 220
    png = client.post("/v1/window.png", json=req)
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content[:8] == b"\x89PNG\r\n\x1a\n"


# -- reload -------------------------------------------------------------------------------------
def test_reload_swaps_model_without_failing_requests(tmp_path: Path) -> None:
    """Four clients query a real server while the model folder is rewritten and
    reloaded five times: no request fails, and after the last reload the
    answers are the new model's."""
    a, b = synthetic_model(seed=4), synthetic_model(seed=11)
    folder = tmp_path / "m"
    a.save(folder, export=False)
    reg = ModelRegistry({"m": folder})
    frame = reg.get().vocab.frame_from_mapping(CONDITION)
    rate_a = float(a.predict(frame)["damage_rate_per_h"].iloc[0])
    rate_b = float(b.predict(frame)["damage_rate_per_h"].iloc[0])
    assert not np.isclose(rate_a, rate_b, rtol=1e-3)
    failures: list[str] = []
    seen: set[int] = set()
    stop = threading.Event()
    with running_server(create_app(reg)) as url:
        def hammer() -> None:
            with httpx.Client(base_url=url, timeout=30.0) as c:
                while not stop.is_set():
                    resp = c.post("/v1/query", json={"rows": [CONDITION]})
                    if resp.status_code != 200:
                        failures.append(resp.text)
                    else:
                        seen.add(resp.json()["generation"])

        threads = [threading.Thread(target=hammer) for _ in range(4)]
        for t in threads:
            t.start()
        with httpx.Client(base_url=url, timeout=60.0) as c:
            for k in range(5):
                (b if k % 2 == 0 else a).save(folder, export=False)
                r = c.post("/v1/model/reload", json={})
                assert r.status_code == 200, r.text
                assert r.json()["reloaded"][0]["generation"] == k + 2
            last = c.post("/v1/query", json={"rows": [CONDITION]}).json()
        stop.set()
        for t in threads:
            t.join()
    assert failures == []
    assert len(seen) >= 2  # requests were answered by more than one generation
    assert last["generation"] == 6
    assert np.isclose(last["rows"][0]["damage_rate_per_h"], rate_b, rtol=RTOL)
    assert np.isclose(rate_b, float(Surrogate.load(folder).predict(frame)
                                    ["damage_rate_per_h"].iloc[0]), rtol=RTOL)


def test_failed_reload_keeps_the_old_model(tmp_path: Path, folders: dict[str, Path]) -> None:
    import shutil

    folder = tmp_path / "m"
    shutil.copytree(folders["synthetic"], folder)
    reg = ModelRegistry({"m": folder})
    c = TestClient(create_app(reg))
    (folder / "metadata.json").unlink()
    r = c.post("/v1/model/reload")
    assert r.status_code == 422 and "not a surrogate model folder" in r.json()["detail"]
    assert c.get("/healthz").json()["models"] == {"m": 1}
    assert c.post("/v1/query", json={"rows": [CONDITION]}).status_code == 200


# -- the serve command: bad options are one line, exit 2, before anything listens -------------
@pytest.mark.parametrize("args, field", [
    (["--model", "/nonexistent/model"], "--model"),
    (["--model", "a b=/tmp"], "--model"),
    (["--model", "MODEL", "--port", "0"], "--port"),
    (["--model", "MODEL", "--max-body-mb", "0"], "--max-body-mb"),
    (["--model", "MODEL", "--torch-threads", "0"], "--torch-threads"),
    (["--model", "MODEL", "--model", "MODEL"], "--model"),
])
def test_serve_bad_options_exit_2(folders: dict[str, Path], capsys, args: list[str],
                                  field: str) -> None:
    argv = ["serve"] + [str(folders["synthetic"]) if a == "MODEL" else a for a in args]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {field}") and err.count("\n") == 1, err


def test_serve_process_answers_and_reloads_on_sighup(folders: dict[str, Path]) -> None:
    """``drillfatigue serve`` as a user starts it: the page, a query, SIGHUP -> generation 2."""
    import os
    import signal
    import time

    from testkit.served import served

    with served(["--model", f"demo={folders['synthetic']}"]) as (url, proc):
        page = httpx.get(url + "/")
        assert page.status_code == 200 and "plotly-cartesian.min.js" in page.text
        assert httpx.get(url + "/static/vendor/plotly-cartesian.min.js").status_code == 200
        q = httpx.post(url + "/v1/query", json={"rows": [CONDITION]}).json()
        assert q["model"] == "demo" and q["generation"] == 1
        os.kill(proc.pid, signal.SIGHUP)
        deadline = time.monotonic() + 60.0
        while httpx.get(url + "/healthz").json()["models"]["demo"] != 2:
            assert time.monotonic() < deadline, "no reload after SIGHUP"
            time.sleep(0.2)
        assert httpx.post(url + "/v1/query", json={"rows": [CONDITION]}).json()["generation"] == 2


def test_impossible_lobe_amplitude_is_422_with_the_pipelines_features(
        tmp_path_factory: pytest.TempPathFactory) -> None:
    """The pipeline's model names the lobe amplitude lobe_amplitude_m: -1 m (or 5 m) in the
    replay's constants used to be answered with a retire list."""
    from testkit.tiny_surrogate import train_tiny_surrogate

    root = Path(__file__).resolve().parents[3]
    folder = train_tiny_surrogate(root / "params.yaml", tmp_path_factory.mktemp("tiny") / "m")
    c = TestClient(create_app(ModelRegistry({"tiny": folder})))
    for value in (-1.0, 5.0):
        r = c.post("/v1/twin/replay", json=_replay_body(
            constants={"lobe_amplitude_m": value, "mu_dynamic": 0.3}))
        assert r.status_code == 422, r.text
        assert r.json()["detail"] == (f"lobe_amplitude_m: {value:g} is outside the physical "
                                      "range (allowed: 0 <= lobe_amplitude_m <= 0.05)")
