"""No number where the model does not know: a domain per component type x location.

A model trained on the design's BHAs (the stand-in of ``tests/testkit/tiny_surrogate``:
collars 4-60 m behind the bit, no collar upset, drill pipe from 60 m) refuses a collar
550 m behind the bit, a collar ``upset``, drill pipe 5 m behind the bit and an rpm
above the design range in ``query``, ``/v1/query``, the twin and the window map. Each
of these was answered "in domain" with a number by the numeric-only domain check.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from testkit.tiny_surrogate import train_tiny_surrogate

from drillfatigue.cli import main
from drillfatigue.surrogate import Surrogate
from drillfatigue.surrogate.twin import replay_log, retire_list, replay_summary
from drillfatigue.surrogate.window import Axis, operating_window

ROOT = Path(__file__).resolve().parents[3]
BASE = {"rpm": 120, "wob_kN": 75, "lobe_amplitude_mm": 1.0, "mud_density_kg_per_m3": 1300,
        "mu_dynamic": 0.3, "local_dls_deg_per_30m": 3, "local_inc_deg": 30,
        "local_max_dls_deg_per_30m": 4, "bit_inc_deg": 40, "bit_dls_deg_per_30m": 3,
        "build_to_bit_deg_per_30m": 3}


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory) -> Path:
    return train_tiny_surrogate(ROOT / "params.yaml", tmp_path_factory.mktemp("m") / "model")


def _flags(**over) -> list[str]:
    row = {**BASE, "md_m": 620, "s_from_bit_m": 30, "component_type": "collar",
           "location": "connection", **over}
    out: list[str] = []
    for k, v in row.items():
        out += [f"--{k.replace('_', '-')}", str(v)]
    return out


def test_an_in_domain_collar_connection_gets_a_number(model_dir: Path, capsys) -> None:
    assert main(["query", "--model", str(model_dir), *_flags(), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["damage_rate_per_h"] > 0


@pytest.mark.parametrize("over, field", [
    # a collar 550 m behind the bit (its MD is outside the collars' too: either is named)
    ({"s_from_bit_m": 550, "md_m": 100}, ("md_m", "s_from_bit_m")),
    ({"location": "upset"}, ("component_type",)),          # collars have no upset
    ({"component_type": "drill_pipe", "s_from_bit_m": 5, "md_m": 600}, ("s_from_bit_m",)),
    ({"rpm": 250}, ("operation.rpm",)),                    # above the design's rpm
])
def test_query_refuses_what_the_model_never_saw(model_dir: Path, capsys, over: dict,
                                                field: tuple[str, ...]) -> None:
    assert main(["query", "--model", str(model_dir), *_flags(**over)]) == 2
    err = capsys.readouterr().err
    assert err.split(":")[1].strip() in field and "no answer" in err, err


def test_the_domain_is_per_component_type_and_location(model_dir: Path) -> None:
    sur = Surrogate.load(model_dir)
    d = sur.domain
    assert "collar upset" not in d.seen_combinations()
    assert {"collar connection", "drill_pipe upset", "stabilizer body"} <= set(
        d.seen_combinations())
    j = sur.features.index("s_from_bit_m")
    lows = dict(zip(d.seen_combinations(), d.group_min_[:, j], strict=True))
    highs = dict(zip(d.seen_combinations(), d.group_max_[:, j], strict=True))
    assert highs["collar body"] < 61.0 and lows["drill_pipe body"] > 59.0


def _service(model_dir: Path):  # noqa: ANN202
    from fastapi.testclient import TestClient

    from drillfatigue.service.app import create_app
    from drillfatigue.service.registry import ModelRegistry
    return TestClient(create_app(ModelRegistry({"default": model_dir})))


def test_the_service_refuses_a_single_row_and_gives_no_number_in_a_batch(model_dir: Path
                                                                          ) -> None:
    client = _service(model_dir)
    good = {**BASE, "md_m": 620, "s_from_bit_m": 30, "component_type": "collar",
            "location": "connection"}
    bad = [{**good, "s_from_bit_m": 550, "md_m": 100}, {**good, "location": "upset"},
           {**good, "component_type": "drill_pipe", "s_from_bit_m": 5}, {**good, "rpm": 250}]
    for row in bad:
        r = client.post("/v1/query", json={"rows": [row]})
        assert r.status_code == 422, (row, r.text)
    r = client.post("/v1/query", json={"rows": [good, *bad]})
    assert r.status_code == 200, r.text
    rows = r.json()["rows"]
    assert rows[0]["damage_rate_per_h"] > 0 and not rows[0]["ood"]
    for row in rows[1:]:
        assert row["ood"] and row["damage_rate_per_h"] is None and row["ood_reason"]


def _log(rpm: float = 120.0) -> pd.DataFrame:
    t = np.arange(0.0, 3600.0 + 1.0, 60.0)
    return pd.DataFrame({"time_s": t, "bit_md_m": 600.0 + t * 5e-3, "rpm": rpm,
                         "wob_kN": 75.0})


def _consts() -> dict:
    return {k: v for k, v in BASE.items() if k not in ("rpm", "wob_kN")}


def test_the_twin_lists_every_item_and_counts_no_damage_out_of_domain(model_dir: Path) -> None:
    sur = Surrogate.load(model_dir)
    comps = pd.DataFrame({
        "serial": ["BIT-1", "DC-1-C", "DC-1-U", "DC-far-C", "DP-1-C"],
        "component_type": ["bit", "collar", "collar", "collar", "drill_pipe"],
        "location": ["body", "connection", "upset", "connection", "connection"],
        "s_from_bit_m": [0.2, 30.0, 30.0, 550.0, 200.0]})
    res = replay_log(_log(), comps, sur, _consts())
    c = res.components.set_index("serial")
    assert list(c.index) == list(comps["serial"])  # every item, in order
    assert not c.loc["BIT-1", "covered"] and "bit" in c.loc["BIT-1", "not_covered_reason"]
    assert not c.loc["DC-1-U", "covered"] and "collar upset" in c.loc["DC-1-U",
                                                                        "not_covered_reason"]
    assert np.isnan(c.loc["DC-1-U", "damage"])
    # in domain: a number; a collar 550 m behind the bit: no damage, an hour out of domain
    assert c.loc["DC-1-C", "damage"] > 0 and c.loc["DC-1-C", "ood_time_s"] == 0
    assert c.loc["DC-far-C", "damage"] == 0 and c.loc["DC-far-C", "ood_time_s"] == 3600.0
    s = replay_summary(res)
    assert s["max_damage_serial"] in ("DC-1-C", "DP-1-C")
    assert {e["item"] for e in s["not_covered"]} == {"BIT-1", "DC-1-U"}
    actions = {e["serial"]: e["action"] for e in retire_list(res, 0.5)}
    assert actions == {"DC-far-C": "inspect", "BIT-1": "not covered",
                       "DC-1-U": "not covered"}


def test_a_twin_replay_entirely_out_of_domain_gives_no_number(model_dir: Path) -> None:
    sur = Surrogate.load(model_dir)
    comps = pd.DataFrame({"serial": ["DC-1-C"], "component_type": ["collar"],
                          "location": ["connection"], "s_from_bit_m": [30.0]})
    res = replay_log(_log(rpm=250.0), comps, sur, _consts())
    s = replay_summary(res)
    assert s["max_damage_in_domain"] is None and s["max_damage_serial"] is None
    assert s["ood_location_hours"] == pytest.approx(1.0)
    assert res.components["damage"].iloc[0] == 0.0


def test_the_window_map_has_no_life_out_of_domain(model_dir: Path) -> None:
    sur = Surrogate.load(model_dir)
    fixed = {**_consts(), "md_m": 620, "s_from_bit_m": 30, "component_type": "collar",
             "location": "connection"}
    wmap = operating_window(sur, Axis.linear("rpm", 40, 220, 10), Axis.in_domain("wob_kN", sur,
                                                                                  5), fixed)
    assert wmap.ood.any() and (~wmap.ood).any()
    assert np.all(np.isnan(wmap.life_h[wmap.ood])) and np.all(wmap.life_h[~wmap.ood] > 0)
    y = Axis.in_domain("wob_kN", sur, 5).values
    assert y[0] == pytest.approx(30.0) and y[-1] == pytest.approx(120.0)


def test_a_batch_answers_an_unseen_type_no_answer_row_by_row(model_dir: Path, tmp_path: Path
                                                             ) -> None:
    """A bit or a motor in a batch of conditions is that row's "no answer" with the reason;
    the other rows are answered (the whole batch was refused before)."""
    rows = pd.read_csv(ROOT / "data" / "examples" / "conditions.csv")
    rows.loc[1, "component_type"] = "bit"
    cond = tmp_path / "c.csv"
    rows.to_csv(cond, index=False)
    out = tmp_path / "p.csv"
    assert main(["query", "--model", str(model_dir), "--csv", str(cond), "--out", str(out)]) == 0
    p = pd.read_csv(out)
    assert p.loc[1, "ood"] and "component_type 'bit'" in p.loc[1, "ood_reason"]
    assert np.isnan(p.loc[1, "damage_rate_per_h"]) and p.loc[0, "damage_rate_per_h"] > 0
    client = _service(model_dir)
    body = client.post("/v1/query", json={"rows": rows.to_dict(orient="records")})
    assert body.status_code == 200, body.text
    api = body.json()["rows"]
    assert api[1]["ood"] and api[1]["damage_rate_per_h"] is None
    assert "component_type 'bit'" in api[1]["ood_reason"] and api[0]["damage_rate_per_h"] > 0
    one = client.post("/v1/query", json={"rows": rows.iloc[[1]].to_dict(orient="records")})
    assert one.status_code == 422 and "bit" in one.json()["detail"]
