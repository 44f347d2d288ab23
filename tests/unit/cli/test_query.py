"""``drillfatigue query``: user units at the boundary, single and batch queries, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from testkit.tiny_surrogate import train_tiny_surrogate

from drillfatigue import units
from drillfatigue.cli import main
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.io.names import Vocabulary
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset

TINY = SurrogateConfig(hidden_layers=(16,), max_epochs=6, patience=6, batch_size=128,
                       n_threads=1)
ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "data" / "examples"
FLAGS = ["--rpm", "120", "--wob-kN", "80", "--rop-m-per-h", "20", "--mu-static", "0.35",
         "--mu-dynamic", "0.28", "--mud-density-sg", "1.25", "--amplitude-mm", "1.0",
         "--lobes", "3", "--kop-m", "500", "--dls-deg-per-30m", "5", "--md-m", "1400",
         "--s-from-bit-m", "40", "--local-dls-deg-per-30m", "0", "--component-type", "collar",
         "--location", "connection", "--profile", "build_hold"]


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("q") / "model"
    fit_surrogate(make_synthetic_dataset(30, seed=3), TINY).save(d, export=False)
    return d


@pytest.fixture(scope="module")
def params_model_dir(tmp_path_factory) -> Path:
    """A model with the inputs of params.yaml (those of data/examples/conditions.csv)."""
    return train_tiny_surrogate(ROOT / "params.yaml", tmp_path_factory.mktemp("p") / "model")


def test_vocabulary_converts_user_units() -> None:
    v = Vocabulary(["operation.wob_N", "operation.rop_m_per_s", "operation.rpm",
                    "operation.mud_density_kg_per_m3", "well.dls_deg_per_30m"], ["location"])
    f = v.frame_from_mapping({"wob_kN": "80", "rop_m_per_h": 36, "rpm": 120,
                              "mud_density_ppg": 10, "dls_deg_per_100ft": 3,
                              "location": "body"})
    assert f["operation.wob_N"].iloc[0] == pytest.approx(80e3)
    assert f["operation.rop_m_per_s"].iloc[0] == pytest.approx(0.01)
    assert f["operation.mud_density_kg_per_m3"].iloc[0] == pytest.approx(
        10 * units.PPG_KG_PER_M3)
    assert f["operation.mud_density_kg_per_m3"].iloc[0] == pytest.approx(1198.26, abs=0.01)
    assert f["well.dls_deg_per_30m"].iloc[0] == pytest.approx(3 * 30 / 30.48)
    # the SI column name itself is accepted; two names for one feature are not
    g = v.frame_from_mapping({"operation.wob_N": 8e4, "rop_m_per_s": 0.01, "rpm": 1,
                              "mud_density_sg": 1.2, "dls_deg_per_30m": 3, "location": "x"})
    assert g["operation.wob_N"].iloc[0] == 8e4
    with pytest.raises(InputError, match="given twice"):
        v.frame_from_table(pd.DataFrame({"wob_kN": [1.0], "wob_N": [1.0]}), require=())


def test_single_query_json(model_dir: Path, capsys) -> None:
    assert main(["query", "--model", str(model_dir), *FLAGS, "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    lo, hi = res["damage_rate_per_h_interval"]
    assert lo < res["damage_rate_per_h"] < hi
    assert res["life_h"] == pytest.approx(1.0 / res["damage_rate_per_h"])
    assert res["inputs_si"]["operation.wob_N"] == pytest.approx(80e3)
    assert res["inputs_si"]["operation.rop_m_per_s"] == pytest.approx(20 / 3600)
    # same number through the Python API on the SI frame
    sur = Surrogate.load(model_dir)
    frame = pd.DataFrame({k: [v] for k, v in res["inputs_si"].items()})
    assert sur.predict(frame)["damage_rate_per_h"].iloc[0] == pytest.approx(
        res["damage_rate_per_h"], rel=1e-12)
    assert res["out_of_domain"] is False
    assert res["horizon_h"] == TINY.horizon_h
    assert res["beyond_horizon"] is (res["life_h"] > res["horizon_h"])


def test_text_output_says_longer_than_the_horizon(model_dir: Path, tmp_path: Path,
                                                   capsys) -> None:
    assert main(["query", "--model", str(model_dir), *FLAGS, "--json"]) == 0
    life_h = json.loads(capsys.readouterr().out)["life_h"]
    # the same model with a horizon below that life answers "longer than"
    sur = Surrogate.load(model_dir)
    sur.metadata["horizon_h"] = life_h / 10.0
    sur.save(tmp_path / "m", export=False)
    assert main(["query", "--model", str(tmp_path / "m"), *FLAGS]) == 0
    out = capsys.readouterr().out
    assert f"longer than the horizon {life_h / 10.0:.4g} h" in out
    assert main(["query", "--model", str(model_dir), *FLAGS]) == 0
    assert f"life: {life_h:.4g} h" in capsys.readouterr().out


@pytest.mark.parametrize("json_flag", [[], ["--json"]])
def test_out_of_domain_query_is_refused(model_dir: Path, capsys, json_flag) -> None:
    """rpm 400 is physical but outside the training data: no number, exit 2, one line
    naming the variable and the range the model answers."""
    flags = list(FLAGS)
    flags[flags.index("--rpm") + 1] = "400"
    assert main(["query", "--model", str(model_dir), *flags, *json_flag]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    lo, hi = Surrogate.load(model_dir).domain.min_[0], Surrogate.load(model_dir).domain.max_[0]
    assert cap.err == (f"error: operation.rpm: 400 is outside the surrogate's training data: "
                       f"no answer (allowed: {lo:.6g} <= operation.rpm <= {hi:.6g})\n")


def test_batch_out_of_domain_row_has_no_number(params_model_dir: Path, tmp_path: Path,
                                               capsys) -> None:
    table = pd.read_csv(EXAMPLES / "conditions.csv")
    table.loc[1, "rpm"] = 400.0
    cond = tmp_path / "cond.csv"
    table.to_csv(cond, index=False)
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(params_model_dir), "--csv", str(cond), "--out", str(out)]) == 0
    p = pd.read_csv(out)
    assert p["ood"].tolist()[1] and "operation.rpm=400" in p["ood_reason"][1]
    assert p.loc[1, ["damage_rate_per_h", "life_h", "life_h_lower"]].isna().all()
    assert p.loc[[0, 2], "damage_rate_per_h"].notna().all()


def test_batch_csv(params_model_dir: Path, tmp_path: Path, capsys) -> None:
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(params_model_dir), "--csv", str(EXAMPLES / "conditions.csv"),
                 "--out", str(out)]) == 0
    p = pd.read_csv(out)
    assert len(p) == 3
    assert {"damage_rate_per_h", "life_h", "ood", "rpm"} <= set(p.columns)
    assert np.all(p["damage_rate_per_h_lower"] <= p["damage_rate_per_h_upper"])


@pytest.mark.parametrize("change, field", [
    (("--rpm", None), "rpm"),                   # missing feature
    (("--rpm", "fast"), "rpm"),                 # non-numeric
    (("--rpm", "nan"), "rpm"),                  # NaN
    (("--wob-kN", "--wob-tonnes"), "wob_tonnes"),  # unknown unit
    (("--component-type", "jar"), "component_type"),  # unseen category
])
def test_bad_query_exits_2_one_line(model_dir: Path, capsys, change, field) -> None:
    flags = list(FLAGS)
    i = flags.index(change[0])
    if change[1] is None:
        del flags[i:i + 2]
    elif change[1].startswith("--"):
        flags[i] = change[1]
    else:
        flags[i + 1] = change[1]
    assert main(["query", "--model", str(model_dir), *flags]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and "\n" not in err and field in err
    assert "Traceback" not in err


def test_bad_batch_writes_nothing(model_dir: Path, tmp_path: Path, capsys) -> None:
    table = pd.read_csv(EXAMPLES / "conditions.csv")
    table.loc[1, "wob_kN"] = np.nan
    bad = tmp_path / "bad.csv"
    table.to_csv(bad, index=False)
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(model_dir), "--csv", str(bad), "--out", str(out)]) == 2
    assert "wob_kN" in capsys.readouterr().err
    assert not out.exists()
    table = pd.read_csv(EXAMPLES / "conditions.csv").rename(columns={"rpm": "rpm_hz"})
    table.to_csv(bad, index=False)
    assert main(["query", "--model", str(model_dir), "--csv", str(bad), "--out", str(out)]) == 2
    assert "rpm_hz" in capsys.readouterr().err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [bad]


def test_missing_model_folder(tmp_path: Path, capsys) -> None:
    assert main(["query", "--model", str(tmp_path / "nope"), *FLAGS]) == 2
    assert "--model" in capsys.readouterr().err


def test_well_gives_the_geometry_features(tmp_path: Path, capsys) -> None:
    """--well: the geometry features equal position_features of that well's survey
    at md_m and md_m + s_from_bit_m, as if given as flags."""
    from drillfatigue.config import load_params
    from drillfatigue.well import build_survey
    from drillfatigue.well.features import survey_features

    params = Path(__file__).resolve().parents[3] / "params.yaml"
    survey = build_survey(load_params(params).well, "profile_1")
    cols = ("local_inc_deg", "bit_inc_deg", "local_max_dls_deg_per_30m")
    data = make_synthetic_dataset(30, seed=3)
    md = data["md_m"].to_numpy()
    data = data.assign(**survey_features(survey, md, md + data["s_from_bit_m"].to_numpy(), cols))
    d = tmp_path / "geo_model"
    fit_surrogate(data, TINY.model_copy(update={"features": TINY.features + cols})).save(
        d, export=False)
    i = FLAGS.index("--local-dls-deg-per-30m")
    base = FLAGS[:i] + FLAGS[i + 2:]  # every geometry feature comes from the well
    base[base.index("--md-m") + 1] = "900"  # within profile_1 (TD 1021 m), bit at 940 m
    assert main(["query", "--model", str(d), *base, "--well", str(params), "--well-profile",
                 "profile_1", "--json"]) == 0
    derived = json.loads(capsys.readouterr().out)
    geo = ("local_dls_deg_per_30m", *cols)
    g = survey_features(survey, np.array([900.0]), np.array([940.0]), geo)
    explicit = [x for c in geo for x in (f"--{c.replace('_', '-')}", repr(float(g[c][0])))]
    assert main(["query", "--model", str(d), *base, *explicit, "--json"]) == 0
    given = json.loads(capsys.readouterr().out)
    for c in geo:
        assert derived["inputs_si"][c] == pytest.approx(float(g[c][0]), rel=1e-15)
    assert derived["log10_damage_rate_per_h"] == pytest.approx(
        given["log10_damage_rate_per_h"], abs=1e-12)
    # both at once, or a profile without a well: one-line errors, exit 2
    assert main(["query", "--model", str(d), *base, *explicit, "--well", str(params)]) == 2
    assert "given together with --well" in capsys.readouterr().err
    assert main(["query", "--model", str(d), *base, "--well-profile", "profile_1"]) == 2
    assert "--well-profile" in capsys.readouterr().err
    assert main(["query", "--model", str(d), *base, "--well", str(params), "--well-profile",
                 "nope"]) == 2
    assert "unknown profile" in capsys.readouterr().err
    # the batch path derives the same values and writes them beside the inputs
    table = pd.DataFrame({base[k][2:].replace("-", "_"): [base[k + 1]] * 2
                          for k in range(0, len(base), 2)})
    table.to_csv(tmp_path / "c.csv", index=False)
    assert main(["query", "--model", str(d), "--csv", str(tmp_path / "c.csv"), "--out",
                 str(tmp_path / "p.csv"), "--well", str(params), "--well-profile",
                 "profile_1"]) == 0
    out = pd.read_csv(tmp_path / "p.csv")
    np.testing.assert_allclose(out["local_inc_deg"], g["local_inc_deg"][0], rtol=1e-12)
    # float32 network: batch-size dependent round-off ~1e-7 in log10 (see test_twin)
    np.testing.assert_allclose(out["log10_damage_rate_per_h"],
                               given["log10_damage_rate_per_h"], atol=1e-6)
    # a location below the well's TD is an input error, not an extrapolation
    flags = list(base)
    flags[flags.index("--md-m") + 1] = "5000"
    assert main(["query", "--model", str(d), *flags, "--well", str(params), "--well-profile",
                 "profile_1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: md_m: 5000 m is beyond the well's total depth ")
    assert err.count("\n") == 1


@pytest.mark.parametrize("flag, value, word", [
    ("--rpm", "1e9", "0 <= rpm <= 1000"),                  # no rig turns this fast
    ("--rpm", "-50", "0 <= rpm <= 1000"),                  # backwards would unscrew the string
    ("--mud-density-sg", "-1", "0 <= mud_density_sg <= 3"),  # negative density
    ("--md-m", "99999", "0 <= md_m <= 20000"),             # deeper than any well
    ("--wob-kN", "-10", "0 <= wob_kN <= 1000"),            # WOB is a compression
])
def test_physically_absurd_query_is_an_input_error(model_dir: Path, capsys, flag, value,
                                                   word) -> None:
    flags = list(FLAGS)
    flags[flags.index(flag) + 1] = value
    assert main(["query", "--model", str(model_dir), *flags]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    name = flag[2:].replace("-", "_")
    assert err.startswith(f"error: {name}: ") and "outside the physical range" in err
    assert f"(allowed: {word})" in err


def test_physical_but_untrained_value_is_refused_not_bounded(model_dir: Path, capsys) -> None:
    """rpm 900 is physical (motor drilling) but far outside the training data: refused
    by the surrogate's domain, not by the physical bounds."""
    flags = list(FLAGS)
    flags[flags.index("--rpm") + 1] = "900"
    assert main(["query", "--model", str(model_dir), *flags, "--json"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: operation.rpm: 900 is outside the surrogate's")
    assert "physical range" not in err


def test_batch_absurd_row_named(model_dir: Path, tmp_path: Path, capsys) -> None:
    table = pd.read_csv(EXAMPLES / "conditions.csv")
    table.loc[2, "rpm"] = 5000.0
    bad = tmp_path / "bad.csv"
    table.to_csv(bad, index=False)
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(model_dir), "--csv", str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: rpm: 5000 is outside the physical range (row 3)")
    assert not out.exists()


def _csv_with(text_of: object, tmp_path: Path) -> Path:
    lines = (EXAMPLES / "conditions.csv").read_text().splitlines()
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(text_of(lines)) + "\n")
    return bad


def _cells(line: str, j: int, value: str) -> str:
    cells = line.split(",")
    cells[j] = value
    return ",".join(cells)


@pytest.mark.parametrize("edit, message", [
    # an empty cell: pandas reads NaN, the message named no row
    (lambda ls: [ls[0], ls[1], _cells(ls[2], 1, "")] + ls[3:],
     "error: {col1}: empty cell (row 2) (allowed: a value in every row)"),
    # a row a cell short: pandas fills NaN
    (lambda ls: [ls[0], ls[1], ls[2], ls[3].rsplit(",", 1)[0]] + ls[4:],
     "error: {csv}: row 3 has {short} cells, the header {n} (allowed: one cell per column "
     "in every row)"),
    # a row a cell long: pandas shifts the first column into the index
    (lambda ls: [ls[0], ls[1] + ",7"] + ls[2:],
     "error: {csv}: row 1 has {long} cells, the header {n} (allowed: one cell per column "
     "in every row)"),
    # a column named twice: pandas renames the second rpm.1
    (lambda ls: [ls[0] + ",rpm"] + [line + ",100" for line in ls[1:]],
     "error: {csv}: column 'rpm' named twice in the header (allowed: each name once)"),
    # a non-numeric cell names its row
    (lambda ls: [ls[0], ls[1], ls[2], _cells(ls[3], 0, "fast")] + ls[4:],
     "error: {col0}: non-numeric value 'fast' (row 3) (allowed: a finite number)"),
])
def test_batch_csv_shape_errors_name_the_row(params_model_dir: Path, tmp_path: Path, capsys,
                                             edit: object, message: str) -> None:
    bad = _csv_with(edit, tmp_path)
    header = (EXAMPLES / "conditions.csv").read_text().splitlines()[0].split(",")
    out = tmp_path / "pred.csv"
    assert main(["query", "--model", str(params_model_dir), "--csv", str(bad), "--out", str(out)]) == 2
    n = len(header)
    assert capsys.readouterr().err == message.format(
        csv=bad, n=n, short=n - 1, long=n + 1, col0=header[0], col1=header[1]) + "\n"
    assert not out.exists()


def test_batch_out_an_existing_folder_is_one_line(params_model_dir: Path, tmp_path: Path,
                                                  capsys) -> None:
    out = tmp_path / "pred"
    out.mkdir()
    (out / "mine.csv").write_text("x\n")
    assert main(["query", "--model", str(params_model_dir), "--csv", str(EXAMPLES / "conditions.csv"),
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"error: --out: {out} is a folder, not a file (allowed: a file path)\n"
    assert [p.name for p in out.iterdir()] == ["mine.csv"]


def test_batch_csv_with_field_headers(params_model_dir: Path, tmp_path: Path) -> None:
    # the example conditions with an engineer's headers and units give the same predictions
    si = pd.read_csv(EXAMPLES / "conditions.csv")
    field = si.rename(columns={"rpm": "RPM", "wob_kN": "WOB (klbf)",
                               "mud_density_sg": "Mud Density (ppg)", "md_m": "MD (ft)"})
    field["WOB (klbf)"] = si["wob_kN"] * units.KN_N / units.KLBF_N
    field["Mud Density (ppg)"] = si["mud_density_sg"] * units.SG_KG_PER_M3 / units.PPG_KG_PER_M3
    field["MD (ft)"] = si["md_m"] / units.FT_M
    field.to_csv(tmp_path / "f.csv", index=False)
    for name, src in (("a.csv", EXAMPLES / "conditions.csv"), ("b.csv", tmp_path / "f.csv")):
        assert main(["query", "--model", str(params_model_dir), "--csv", str(src), "--out",
                     str(tmp_path / name)]) == 0
    a, b = pd.read_csv(tmp_path / "a.csv"), pd.read_csv(tmp_path / "b.csv")
    # unit conversions there and back differ from the SI inputs by ~1e-16 relative,
    # far below what moves the float32 network's output
    np.testing.assert_allclose(b["damage_rate_per_h"], a["damage_rate_per_h"], rtol=1e-6)


def test_batch_output_never_replaces_an_input(model_dir: Path, tmp_path: Path, capsys) -> None:
    """--out naming the conditions CSV itself (by any path, a link included) or a file in
    the model folder would lose an input: one line, exit 2, nothing changed."""
    cond = tmp_path / "cond.csv"
    cond.write_bytes((EXAMPLES / "conditions.csv").read_bytes())
    link = tmp_path / "link.csv"
    link.symlink_to(cond)
    model_before = {p.name: p.read_bytes() for p in model_dir.iterdir() if p.is_file()}
    for out, word in ((cond, "is the --csv input"), (tmp_path / "." / "cond.csv", "--csv"),
                      (link, "--csv"), (model_dir / "notes.csv", "inside the --model folder")):
        assert main(["query", "--model", str(model_dir), "--csv", str(cond),
                     "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: --out:") and word in err and err.count("\n") == 1
        assert cond.read_bytes() == (EXAMPLES / "conditions.csv").read_bytes()
    assert not (model_dir / "notes.csv").exists()
    assert {p.name: p.read_bytes() for p in model_dir.iterdir() if p.is_file()} == model_before
    # the predictions are CSV text: another suffix would mislabel them
    assert main(["query", "--model", str(model_dir), "--csv", str(cond),
                 "--out", str(tmp_path / "pred.parquet")]) == 2
    assert "not a .csv file" in capsys.readouterr().err
    assert not (tmp_path / "pred.parquet").exists()


def test_messages_show_table_values_as_plain_values() -> None:
    """A value read from a table is a numpy scalar: the message shows 'banana' and nan,
    not np.str_('banana') and np.float64(nan)."""
    v = Vocabulary(["operation.rpm"], [])
    for value, shown in ((np.str_("banana"), "'banana'"), (np.float64("nan"), "nan")):
        with pytest.raises(InputError) as exc:
            v.frame_from_table(pd.DataFrame({"rpm": np.array([value], dtype=object)}),
                               require=())
        assert shown in exc.value.problem and "np." not in str(exc.value)
