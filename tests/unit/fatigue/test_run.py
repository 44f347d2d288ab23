"""evaluate_run and the ``drillfatigue fatigue`` command on synthetic run directories."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue.cli import main
from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.errors import InputError
from drillfatigue.fatigue.run import DAMAGE_COLUMNS, evaluate_run

from testkit.fatigue_runs import write_run_dir

FAST = dict(plane_step_deg=15.0, n_refine=1)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run_dir(tmp_path_factory.mktemp("run") / "r", n_joints=3, n_t=1000)


def test_evaluate_run_writes_one_row_per_joint_and_location(run_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "fat"
    df = evaluate_run(run_dir, FatigueConfig(**FAST), out)
    assert list(df.columns) == list(DAMAGE_COLUMNS)
    # drill-pipe joints add the upset run-out (body section, upset SCFs)
    types = df.groupby("joint")["component_type"].first()
    n_upset = int((types == "drill_pipe").sum())
    assert len(df) == 6 + n_upset and set(df["location"]) == (
        {"body", "connection", "upset"} if n_upset else {"body", "connection"})
    up = df[df["location"] == "upset"].set_index("joint")["damage"]
    body = df[df["location"] == "body"].set_index("joint")["damage"]
    assert (up > body.loc[up.index]).all()  # SCF 2 on the same section
    assert (df["damage"] > 0).all()
    dur_h = 1.0 / 3600  # 1000 samples of 1 ms
    np.testing.assert_allclose(df["damage_rate_per_h"], df["damage"] / dur_h, rtol=1e-12)
    np.testing.assert_allclose(df["life_h"] * df["damage"], dur_h, rtol=1e-12)
    np.testing.assert_allclose(df["life_windows"] * df["damage"], 1.0, rtol=1e-12)
    back = pd.read_parquet(out / "damage.parquet")
    pd.testing.assert_frame_equal(back, df)
    summ = json.loads((out / "summary.json").read_text())
    assert summ["governing"]["damage"] == pytest.approx(df["damage"].max())
    for png in ("stress_history.png", "rainflow_matrix.png", "damage_along_string.png"):
        assert (out / png).stat().st_size > 1000


def test_joint_selection_and_criterion_override(run_dir: Path) -> None:
    df = evaluate_run(run_dir, FatigueConfig(upset_location=False, **FAST), joints=[1],
                      criterion="uniaxial")
    assert df["joint"].tolist() == [1, 1] and (df["criterion"] == "uniaxial").all()
    np.testing.assert_allclose(df["damage"], df["uniaxial_damage"], rtol=1e-12)


def test_carry_residue_streams_the_uniaxial_route(run_dir: Path) -> None:
    half = evaluate_run(run_dir, FatigueConfig(criterion="uniaxial", residue="half", **FAST))
    carry = evaluate_run(run_dir, FatigueConfig(criterion="uniaxial", residue="carry",
                                                chunk_length_s=0.137, **FAST))
    # streaming with carried residue = whole-history ASTM count (1e-9 relative)
    np.testing.assert_allclose(carry["damage"], half["damage"], rtol=1e-9)


def test_cli_writes_outputs(run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
                            ) -> None:
    out = tmp_path / "cli"
    rc = main(["fatigue", str(run_dir), "--out", str(out), "--criterion", "findley",
               "--joints", "0,2"])
    assert rc == 0
    df = pd.read_parquet(out / "damage.parquet")
    assert sorted(df["joint"].unique()) == [0, 2] and (df["criterion"] == "findley").all()


def _bad_runs(tmp: Path) -> dict[str, tuple[list[str], str]]:
    ok = write_run_dir(tmp / "ok", n_joints=1, n_t=300)
    params = tmp / "params.yaml"
    params.write_text("fatigue:\n  body:\n    curve: Q9\n")
    return {
        "missing_column": ([str(write_run_dir(tmp / "m", n_joints=1, n_t=300,
                                              drop_column="torque_Nm"))], "torque_Nm"),
        "nan": ([str(write_run_dir(tmp / "n", n_joints=1, n_t=300, nan=True))], "NaN"),
        "unknown_criterion": ([str(ok), "--criterion", "tresca"], "allowed"),
        "unknown_curve": ([str(ok), "--params", str(params)], "Q9"),
        "zero_length": ([str(write_run_dir(tmp / "z", n_joints=1, n_t=0))], "zero-length"),
        "incomplete": ([str(write_run_dir(tmp / "i", n_joints=1, n_t=300,
                                          status="incomplete"))], "incomplete"),
        "unknown_joint": ([str(ok), "--joints", "7"], "joint 7"),
    }


@pytest.mark.parametrize("case", ["missing_column", "nan", "unknown_criterion", "unknown_curve",
                                  "zero_length", "incomplete", "unknown_joint"])
def test_bad_input_one_line_exit_2_nothing_written(case: str, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    args, needle = _bad_runs(tmp_path)[case]
    out = tmp_path / "out"
    rc = main(["fatigue", *args[:1], "--out", str(out), *args[1:]])
    err = capsys.readouterr().err
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0]
    assert "Traceback" not in err
    assert not out.exists()


def test_api_rp7g_side_by_side_from_the_run_case(tmp_path: Path) -> None:
    import yaml

    from drillfatigue.fatigue.rp7g import lubinski_bending_stress_Pa
    from drillfatigue.fatigue.sn import get_curve

    run = write_run_dir(tmp_path / "r", n_joints=3, n_t=600)  # joints at 500, 491, 482 m MD
    case = yaml.safe_load((Path(__file__).resolve().parents[3] / "data" / "cases"
                           / "vertical_quick.yaml").read_text())
    case["well"] = {"profiles": {"j": {"kind": "j", "kop_m": 400.0, "dls_deg_per_30m": 6.0,
                                       "inc_deg": 60.0, "td_m": 1500.0}}}
    case["operation"]["bit_md_m"] = 520.0
    case["operation"]["rpm"] = 90.0
    case["fatigue"] = dict(FAST)
    (run / "case.yaml").write_text(yaml.safe_dump(case))
    out = tmp_path / "fat"
    df = evaluate_run(run, FatigueConfig(**FAST), out)
    rp = pd.read_parquet(out / "api_rp7g.parquet")
    assert rp["joint"].tolist() == [0, 1, 2] and (rp["location"] == "body").all()
    # all three joints sit in the 6 deg/30 m build (400 m to 700 m MD)
    np.testing.assert_allclose(rp["hole_dls_deg_per_30m"], 6.0, rtol=1e-6)
    # joint 1 by hand: Lubinski stress, fully reversed range 2 sigma_b with Goodman on
    # the mean tension stress, B1 curve, one cycle per revolution at 90 rpm
    ld = pd.read_parquet(run / "loads.parquet")
    T = ld.loc[ld["joint"] == 1, "axial_N"].mean()
    od, idm = 0.127, 0.1086
    A, I = np.pi * (od**2 - idm**2) / 4, np.pi * (od**4 - idm**4) / 64
    kappa = np.radians(6.0) / 30.0
    sb = lubinski_bending_stress_Pa(207e9, od, kappa, T, I, 4.572)
    su = 145_000 * 6894.757293168
    S = 2 * sb / (1 - (T / A) / su)
    rate = 90 * 60 / get_curve("B1").cycles_to_failure(S)[0]
    assert rp.loc[1, "rp7g_damage_rate_per_h"] == pytest.approx(rate, rel=1e-9)
    body = df[df["location"] == "body"].set_index("joint")["damage_rate_per_h"]
    np.testing.assert_allclose(rp["dynamic_damage_rate_per_h"], body.loc[[0, 1, 2]], rtol=1e-12)
    np.testing.assert_allclose(rp["dynamic_to_rp7g_ratio"],
                               rp["dynamic_damage_rate_per_h"] / rp["rp7g_damage_rate_per_h"])
    # S-135 endurance line: a finite permissible dogleg, lower for more tension
    assert np.all(np.isfinite(rp["max_permissible_dls_deg_per_30m"]))
    summ = json.loads((out / "summary.json").read_text())
    assert summ["api_rp7g"]["max_damage_rate_per_h"] == pytest.approx(
        rp["rp7g_damage_rate_per_h"].max())
    # without a full case (only a fatigue section) there is no baseline file
    out2 = tmp_path / "fat2"
    evaluate_run(write_run_dir(tmp_path / "r2", n_joints=1, n_t=300), FatigueConfig(**FAST), out2)
    assert not (out2 / "api_rp7g.parquet").exists()


def test_out_folder_with_a_users_file_is_refused_at_once(run_dir: Path, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str],
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """`fatigue --out DIR` with a user's file in DIR, or `--out FILE`: exit 2, one line,
    before the run is even read (checked: the loader is never called), and the user's
    file is untouched."""
    import drillfatigue.fatigue.run as run_mod

    def no_work(*_a: object, **_k: object) -> None:
        raise AssertionError("the run was read before the output was checked")

    monkeypatch.setattr(run_mod, "read_run", no_work)
    mine = tmp_path / "results"
    mine.mkdir()
    (mine / "summary.docx").write_bytes(b"my report")
    assert main(["fatigue", str(run_dir), "--out", str(mine)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and err.count("\n") == 1
    assert "did not write" in err
    assert sorted(p.name for p in mine.iterdir()) == ["summary.docx"]
    afile = tmp_path / "damage.txt"
    afile.write_text("x")
    assert main(["fatigue", str(run_dir), "--out", str(afile)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and "is a file" in err and err.count("\n") == 1
    assert afile.read_text() == "x"


def test_rerun_replaces_only_its_own_files(run_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "fat"
    evaluate_run(run_dir, FatigueConfig(**FAST), out)
    (out / "notes.txt").write_text("mine")
    evaluate_run(run_dir, FatigueConfig(plots=False, **FAST), out)  # drops its own figures
    names = sorted(p.name for p in out.iterdir())
    assert names == [".drillfatigue.json", "damage.parquet", "notes.txt", "summary.json"]
    assert (out / "notes.txt").read_text() == "mine"


def test_a_foreign_file_of_an_output_name_is_refused_before_anything_is_rewritten(
        run_dir: Path, tmp_path: Path, capsys) -> None:
    """An evaluation without figures, then the user's own figure under the name a plot
    would take: an evaluation with plots is refused before it rewrites the old outputs."""
    out = tmp_path / "fat"
    evaluate_run(run_dir, FatigueConfig(plots=False, **FAST), out)
    (out / "damage_along_string.png").write_bytes(b"my figure")
    before = {p.name: (p.stat().st_ino, p.read_bytes()) for p in out.iterdir()}
    with pytest.raises(InputError, match="damage_along_string.png exists and was not written"):
        evaluate_run(run_dir, FatigueConfig(**FAST), out)
    assert main(["fatigue", str(run_dir), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --out:") and "\n" not in err
    assert {p.name: (p.stat().st_ino, p.read_bytes()) for p in out.iterdir()} == before


def test_joint_pressures_are_hydrostatic_at_the_joint_tvd() -> None:
    from drillfatigue.config import CaseConfig
    from drillfatigue.fatigue.run import joint_pressures
    from drillfatigue.well import build_survey

    case = CaseConfig()
    sv = build_survey(case.well)
    md = {0: 10.0, 1: float(sv.md_m[-1]) * 0.9}
    p = joint_pressures(case, md, 2e6)
    rho = case.operation.mud_density_kg_per_m3
    for j, m in md.items():
        tvd = float(np.interp(m, sv.md_m, sv.pos_m[:, 2]))
        assert p[j].external_Pa == pytest.approx(rho * 9.80665 * tvd, rel=1e-12)
        assert p[j].internal_Pa == pytest.approx(p[j].external_Pa + 2e6, rel=1e-12)


def test_run_case_mud_pressure_reaches_the_criteria(tmp_path: Path) -> None:
    import yaml

    run = write_run_dir(tmp_path / "r", n_joints=2, n_t=600)
    case = yaml.safe_load((Path(__file__).resolve().parents[3] / "data" / "cases"
                           / "vertical_quick.yaml").read_text())
    case["operation"]["bit_md_m"] = 520.0
    cfg = dict(FAST, upset_location=False)
    dry = evaluate_run(run, FatigueConfig(pressure=False, **cfg))
    for rho, same in ((0.0, True), (1500.0, False)):
        case["operation"]["mud_density_kg_per_m3"] = rho
        (run / "case.yaml").write_text(yaml.safe_dump(case))
        wet = evaluate_run(run, FatigueConfig(**cfg))
        if same:  # zero density: zero pressure, bit for bit the dry result
            assert np.array_equal(wet["damage"].to_numpy(), dry["damage"].to_numpy())
        else:  # ~7 MPa hydrostatic compression lowers every plane's normal stress
            assert np.all(wet["damage"].to_numpy() < dry["damage"].to_numpy())


def test_span_bending_columns_add_to_the_joint_moment(tmp_path: Path) -> None:
    run = write_run_dir(tmp_path / "r", n_joints=2, n_t=600)
    base = evaluate_run(run, FatigueConfig(upset_location=False, **FAST))
    ld = pd.read_parquet(run / "loads.parquet")
    # the whole bending moved into the span columns: the same stresses, the same damage
    moved = ld.assign(span_bending_x_Nm=ld["bending_x_Nm"], span_bending_y_Nm=ld["bending_y_Nm"],
                      bending_x_Nm=0.0, bending_y_Nm=0.0)
    moved.to_parquet(run / "loads.parquet", index=False)
    same = evaluate_run(run, FatigueConfig(upset_location=False, **FAST))
    np.testing.assert_allclose(same["damage"], base["damage"], rtol=1e-12)
    # a span correction on top of it raises the damage
    moved.assign(bending_x_Nm=0.5 * ld["bending_x_Nm"]).to_parquet(run / "loads.parquet",
                                                                  index=False)
    more = evaluate_run(run, FatigueConfig(upset_location=False, **FAST))
    assert (more["damage"].to_numpy() > base["damage"].to_numpy()).all()
    moved.drop(columns=["span_bending_y_Nm"]).to_parquet(run / "loads.parquet", index=False)
    with pytest.raises(InputError, match="partner"):
        evaluate_run(run, FatigueConfig(**FAST))
