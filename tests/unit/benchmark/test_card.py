"""The research dataset's card and its Croissant 1.0 metadata.

The Croissant checks follow the Croissant 1.0 specification (MLCommons): a
``sc:Dataset`` with ``name``, ``description``, ``license``, ``url`` and
``conformsTo``; ``cr:FileObject`` distributions with a content URL, encoding
format and SHA-256; ``cr:RecordSet`` s whose ``cr:Field`` s name a data type and a
source (a file object and the column extracted from it). ``mlcroissant`` is
not a dependency of the project; where it is installed it validates the file too.
"""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import pandas as pd
import pytest
import yaml

from drillfatigue.benchmark.card import CROISSANT_CONFORMS_TO, write_card
from drillfatigue.cli import main

DATA = Path(__file__).resolve().parents[2] / "data" / "research_dataset"
SPREAD = {"sigma_log10": 0.12, "ceiling_factor2_fraction": 0.944, "n_cases": 8,
          "n_replicates": 3, "rel_step": 0.01}


@pytest.fixture()
def folder(tmp_path: Path) -> Path:
    out = tmp_path / "dataset"
    out.mkdir()
    for split in ("train", "heldout"):
        shutil.copy(DATA / f"{split}.parquet", out / f"{split}.parquet")
    return out


def test_card_front_matter_and_body(folder: Path, tmp_path: Path) -> None:
    spread = tmp_path / "spread.json"
    spread.write_text(json.dumps(SPREAD))
    card, _ = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="make research",
                         commit="abc123", spread_path=spread)
    text = card.read_text()
    head = yaml.safe_load(text.split("---")[1])
    assert head["license"] == "cc-by-4.0"
    assert head["configs"][0]["data_files"] == [{"split": "train", "path": "train.parquet"},
                                                {"split": "heldout", "path": "heldout.parquet"}]
    meta = head["drillfatigue"]
    assert meta["version"] == "1.0.0" and meta["horizon_h"] == 1e5
    assert meta["n_cases"] == {"train": 6, "heldout": 2}
    cols = meta["columns"]
    assert cols["operation.wob_N"] == {"role": "input", "unit": "N"}
    assert cols["damage_rate_per_h_matake"] == {"role": "target", "unit": "1/h"}
    assert cols["stick_slip_severity"]["role"] == "post_run"
    assert cols["split"]["role"] == "split"
    train = pd.read_parquet(folder / "train.parquet")
    assert [f["name"] for f in head["dataset_info"]["features"]] == list(train.columns)
    assert "`make research`" in text and "`abc123`" in text
    assert "factor-2 ceiling 0.944" in text and "horizon of 100000 h" in text
    assert "| train | `train.parquet` | 6 |" in text


def test_card_without_replicates_says_not_measured(folder: Path) -> None:
    card, _ = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="c",
                         commit="abc")
    assert "Not measured" in card.read_text()


def test_croissant_structure(folder: Path) -> None:
    _, path = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="c",
                         commit="abc")
    doc = json.loads(path.read_text())
    ctx = doc["@context"]
    assert ctx["@vocab"] == "https://schema.org/" and ctx["cr"] == "http://mlcommons.org/croissant/"
    assert doc["@type"] == "sc:Dataset" and doc["conformsTo"] == CROISSANT_CONFORMS_TO
    for key in ("name", "description", "license", "url", "version", "citeAs"):
        assert doc[key], key
    files = {f["@id"]: f for f in doc["distribution"]}
    assert set(files) == {"train.parquet", "heldout.parquet"}
    for f in files.values():
        assert f["@type"] == "cr:FileObject" and f["encodingFormat"] == "application/x-parquet"
        assert f["sha256"] == hashlib.sha256((folder / f["contentUrl"]).read_bytes()).hexdigest()
    ids = set(files)
    for rs in doc["recordSet"]:
        assert rs["@type"] == "cr:RecordSet"
        columns = list(pd.read_parquet(folder / f"{rs['name']}.parquet").columns)
        fields = rs["field"]
        assert [f["name"] for f in fields] == columns
        for f in fields:
            assert f["@type"] == "cr:Field"
            assert f["@id"] not in ids
            ids.add(f["@id"])
            assert f["dataType"] in ("sc:Float", "sc:Integer", "sc:Text", "sc:Boolean")
            assert f["source"]["fileObject"]["@id"] in files
            assert f["source"]["extract"]["column"] == f["name"]
        field_ids = {f["@id"] for f in fields}
        assert all(k["@id"] in field_ids for k in rs["key"])
    by_id = {f["@id"]: f for rs in doc["recordSet"] for f in rs["field"]}
    assert by_id["train/operation.rpm"]["dataType"] == "sc:Float"
    assert "[rev/min]" in by_id["train/operation.rpm"]["description"]
    assert by_id["heldout/joint"]["dataType"] == "sc:Integer"


def test_croissant_validates_with_mlcroissant_where_installed(folder: Path) -> None:
    mlc = pytest.importorskip("mlcroissant")
    _, path = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="c",
                         commit="abc")
    ds = mlc.Dataset(jsonld=str(path))
    records = list(ds.records(record_set="heldout"))
    assert len(records) == len(pd.read_parquet(folder / "heldout.parquet"))


def test_cli_card(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["benchmark", "card", "--dataset", str(folder), "--commit", "abc"]) == 0
    assert (folder / "README.md").is_file() and (folder / "croissant.json").is_file()
    capsys.readouterr()
    assert main(["benchmark", "card", "--dataset", str(folder), "--spread", "nope.json"]) == 2
    assert "--spread: nope.json not found" in capsys.readouterr().err


def test_card_names_the_physics_digest_and_commits_of_the_case_files(folder: Path) -> None:
    from drillfatigue.sweep.research_case import write_case_file

    cases = folder.parent / "cases" / "train"
    for i, commit in enumerate(("a" * 40, "a" * 40, "b" * 40)):
        marker = {"case_id": f"c{i}", "split": "train", "inputs_sha256": "x",
                  "physics_digest": "d" * 64, "commit": commit}
        write_case_file(pd.DataFrame({"case_id": [f"c{i}"], "joint": [0]}),
                        cases / f"c{i}.parquet", marker)
    card, _ = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="cmd")
    text = card.read_text(encoding="utf-8")
    assert f"- physics digest: `{'d' * 16}`" in text
    assert "`aaaaaaa` (2), `bbbbbbb` (1)" in text
    # a dataset with no case files beside it says nothing about them
    shutil.rmtree(folder.parent / "cases")
    card, _ = write_card(folder, rate_floor_per_h=1e-12, horizon_h=1e5, command="cmd")
    assert "physics digest" not in card.read_text(encoding="utf-8")
