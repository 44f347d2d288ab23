"""Digital twin: operating-log replay accumulates rate x time per component."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from testkit.tiny_surrogate import open_domain

from drillfatigue.cli import main
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.twin import _ConditionCache, replay_log

# every row regressed: these tests are about the replay's bookkeeping, and the
# cross-replay bit-equality below holds for these weights (eager and TorchScript
# GEMMs of different row counts may differ in the last bit for other weights)
TINY = SurrogateConfig(hidden_layers=(16,), max_epochs=6, patience=6, batch_size=128,
                       n_threads=1, censoring="none")
EXAMPLES = Path(__file__).resolve().parents[3] / "data" / "examples"
CONSTANTS = {"mu_static": 0.35, "mu_dynamic": 0.28, "mud_density_sg": 1.25,
             "amplitude_mm": 1.0, "lobes": 3, "kop_m": 500, "dls_deg_per_30m": 5,
             "profile": "build_hold", "local_dls_deg_per_30m": 0.0}


@pytest.fixture(scope="module")
def model() -> Surrogate:
    return open_domain(fit_surrogate(make_synthetic_dataset(30, seed=4), TINY))


def _components() -> pd.DataFrame:
    return pd.read_csv(EXAMPLES / "components.csv")


def test_constant_conditions_give_rate_times_T(model: Surrogate) -> None:
    # uneven steps over T = 7.3 h at constant rpm, WOB, ROP and bit depth
    t = np.concatenate([[0.0], np.cumsum(np.random.default_rng(0).uniform(1, 600, 80))])
    t *= 7.3 * 3600 / t[-1]
    log = pd.DataFrame({"time_s": t, "bit_md_m": 1500.0, "rpm": 130.0, "wob_kN": 90.0,
                        "rop_m_per_h": 15.0})
    comps = _components()
    res = replay_log(log, comps, model, CONSTANTS).components
    # the same conditions asked directly, in SI columns
    frame = pd.DataFrame({
        "operation.rpm": 130.0, "operation.wob_N": 90e3, "operation.rop_m_per_s": 15 / 3600,
        "friction.mu_static": 0.35, "friction.mu_dynamic": 0.28,
        "operation.mud_density_kg_per_m3": 1250.0, "bit.amplitude_m": 1e-3, "bit.lobes": 3.0,
        "well.kop_m": 500.0, "well.dls_deg_per_30m": 5.0, "well.profile": "build_hold",
        "local_dls_deg_per_30m": 0.0, "s_from_bit_m": comps["s_from_bit_m"],
        "md_m": 1500.0 - comps["s_from_bit_m"], "component_type": comps["component_type"],
        "location": comps["location"]})
    p = model.predict(frame, refuse=False)  # the twin counts out-of-domain time apart
    T_h = 7.3
    # exact bookkeeping: damage = rate x T at 1e-9 with the rate the twin used
    rate = res["last_damage_rate_per_h"]
    np.testing.assert_allclose(res["damage"], rate * T_h, rtol=1e-9)
    np.testing.assert_allclose(res["remaining_life_h"], (1 - res["damage"]) / rate, rtol=1e-9)
    # and that rate is the model's for these conditions: the float32 network
    # gives batch-size dependent round-off (BLAS blocking) of ~1e-7 in log10,
    # i.e. ~5e-7 relative in the rate; 1e-5 bounds it with margin
    np.testing.assert_allclose(res["damage"], p["damage_rate_per_h"] * T_h, rtol=1e-5)
    np.testing.assert_allclose(res["damage_lower"], p["damage_rate_per_h_lower"] * T_h, rtol=1e-5)
    np.testing.assert_allclose(res["damage_upper"], p["damage_rate_per_h_upper"] * T_h, rtol=1e-5)
    np.testing.assert_allclose(res["time_in_hole_s"], 7.3 * 3600, rtol=1e-12)
    np.testing.assert_allclose(res["ood_time_s"], np.where(p["ood"], 7.3 * 3600, 0.0))


def test_same_conditions_same_rate_wherever_they_fall_in_a_batch(model: Surrogate) -> None:
    # condition A at the start, again after 3000 steps of varying conditions
    # (several surrogate batches later): the rate charged for A must be the
    # same bits, so the damage of A's two stretches is exactly 2 x one of them
    n = 3000
    rpm = np.concatenate([[130.0], np.linspace(60, 180, n), [130.0], [130.0]])
    t = np.arange(rpm.size, dtype=float) * 3600.0
    log = pd.DataFrame({"time_s": t, "bit_md_m": 1500.0, "rpm": rpm, "wob_kN": 90.0,
                        "rop_m_per_h": 15.0})
    comps = _components()
    one = replay_log(log.iloc[[0, 1]], comps, model, CONSTANTS).components
    both = replay_log(log, comps, model, CONSTANTS).components
    assert np.array_equal(both["last_damage_rate_per_h"].to_numpy(),
                          one["last_damage_rate_per_h"].to_numpy())
    # and in one batch: many distinct rows around duplicates of one row
    rng = np.random.default_rng(1)
    x = rng.uniform(0.0, 1.0, (5000, len(model.features)))
    x[::7] = x[3]
    c = np.zeros((5000, len(model.categorical)), dtype=np.int64)
    r = _ConditionCache(model).predict(x, c)
    assert np.unique(r["log10"][::7]).size == 1


def test_components_above_surface_accumulate_nothing(model: Surrogate) -> None:
    # bit at 100 m for 1 h then 300 m for 1 h: components 200 m and 350 m
    # behind the bit are out of the hole for part (all) of the log
    log = pd.DataFrame({"time_s": [0.0, 3600.0, 7200.0], "bit_md_m": [100.0, 300.0, 300.0],
                        "rpm": 120.0, "wob_kN": 80.0, "rop_m_per_h": 10.0})
    res = replay_log(log, _components(), model, CONSTANTS).components.set_index("serial")
    assert res.loc["DP-302-B", "damage"] == 0.0
    assert res.loc["DP-302-B", "time_in_hole_s"] == 0.0
    assert np.isnan(res.loc["DP-302-B", "last_damage_rate_per_h"])
    assert res.loc["DP-301-C", "time_in_hole_s"] == 3600.0
    assert res.loc["STB-001-B", "time_in_hole_s"] == 7200.0
    assert res.loc["STB-001-B", "damage"] > 0


def test_replay_input_errors(model: Surrogate) -> None:
    log = pd.DataFrame({"time_s": [0.0, 10.0], "bit_md_m": 1000.0, "rpm": 120.0,
                        "wob_kN": 80.0, "rop_m_per_h": 10.0})
    with pytest.raises(InputError, match="mu_static"):
        replay_log(log, _components(), model, {k: v for k, v in CONSTANTS.items()
                                                if k != "mu_static"})
    with pytest.raises(InputError, match="given twice"):
        replay_log(log, _components(), model, dict(CONSTANTS, rpm=100))
    with pytest.raises(InputError, match="time"):
        replay_log(log.iloc[::-1], _components(), model, CONSTANTS)
    with pytest.raises(InputError, match="serial"):
        replay_log(log, _components().drop(columns="serial"), model, CONSTANTS)


def test_cli_replay_example_log(model: Surrogate, tmp_path: Path, capsys) -> None:
    model.save(tmp_path / "m", export=False)
    out = tmp_path / "twin"
    sets = [a for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"
            for a in ("--set", f"{k}={v}")]
    rc = main(["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model", str(tmp_path / "m"),
               "--components", str(EXAMPLES / "components.csv"), "--survey",
               str(EXAMPLES / "survey.csv"), *sets, "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    table = pd.read_csv(out / "components_damage.csv")
    assert len(table) == 9 and (table["damage"] > 0).all()
    assert (table["damage_lower"] <= table["damage"]).all()
    assert (out / "damage_along_string.png").stat().st_size > 0
    assert (out / "summary.json").is_file()
    # a bad setting: exit 2, one line, nothing written
    out2 = tmp_path / "twin2"
    rc = main(["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model", str(tmp_path / "m"),
               "--components", str(EXAMPLES / "components.csv"), "--survey",
               str(EXAMPLES / "survey.csv"), *sets, "--set", "kop_m=deep", "--out", str(out2)])
    assert rc == 2
    assert "kop_m" in capsys.readouterr().err
    assert not out2.exists()


STRING_YAML = """\
string:
  components:
    - {type: stabilizer, name: STB, od_m: 0.17, id_m: 0.07, length_m: 2.0, n_segments: 1}
    - {type: collar, name: DC, od_m: 0.17145, id_m: 0.0714, length_m: 60.0, n_segments: 3}
    - {type: hwdp, name: HW, od_m: 0.127, id_m: 0.0762, length_m: 90.0, n_segments: 2}
well:
  profiles:
    j:
      kind: j
      kop_m: 500.0
      dls_deg_per_30m: 5.0
      inc_deg: 60.0
      td_m: 2500.0
"""


def test_components_and_survey_from_config_and_hook_load(model: Surrogate, tmp_path: Path,
                                                          capsys) -> None:
    from drillfatigue.config.base import read_yaml
    from drillfatigue.config import StringConfig, WellConfig, validate
    from drillfatigue.surrogate.twin import components_from_string, survey_from_well

    case = tmp_path / "case.yaml"
    case.write_text(STRING_YAML)
    data = read_yaml(case)
    comps = components_from_string(validate(StringConfig, data["string"], "string"),
                                   locations=("body", "connection"))
    # one body and one connection row per joint between segments, at the joints (the
    # dataset's locations): stabilizer/collar, two collar joints, collar/HWDP, HWDP/HWDP
    assert len(comps) == 2 * 5 and comps["serial"].is_unique
    np.testing.assert_allclose(sorted(set(comps["s_from_bit_m"])),
                               [2.0, 22.0, 42.0, 62.0, 107.0])
    sv = survey_from_well(validate(WellConfig, data["well"], "well"))
    inside = (sv["md_m"] > 510) & (sv["md_m"] < 800)
    np.testing.assert_allclose(sv.loc[inside, "dls_deg_per_30m"], 5.0, rtol=1e-6)
    # hook load channel instead of WOB: WOB = off-bottom - on-bottom hook load
    log = pd.DataFrame({"time_s": [0.0, 1800.0, 3600.0], "bit_md_m": [1000.0, 1005.0, 1010.0],
                        "rpm": 120.0, "hook_load_kN": 920.0, "rop_m_per_h": 10.0})
    consts = {k: v for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"}
    via_hook = replay_log(log, comps, model, dict(consts, off_bottom_hook_load_kN=1000.0),
                          sv).components
    direct = replay_log(log.drop(columns="hook_load_kN").assign(wob_kN=80.0), comps, model,
                        consts, sv).components
    np.testing.assert_allclose(via_hook["damage"], direct["damage"], rtol=1e-12)
    with pytest.raises(InputError, match="off_bottom_hook_load"):
        replay_log(log, comps, model, consts, sv)
    # the CLI with --string/--well (a case file holds both sections)
    model.save(tmp_path / "m", export=False)
    sets = [a for k, v in consts.items() for a in ("--set", f"{k}={v}")]
    out = tmp_path / "twin"
    rc = main(["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model",
               str(tmp_path / "m"), "--string", str(case), "--well", str(case), *sets,
               "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    table = pd.read_csv(out / "components_damage.csv")
    # body and connection of every joint, and the upset of the heavy-weight pipe's two,
    # which this model (trained without upsets) lists as not covered
    assert len(table) == 12 and (table.loc[table["covered"], "damage"] > 0).all()
    assert set(table.loc[~table["covered"], "location"]) == {"upset"}
    # both a string and a component table: exit 2, one line, nothing written
    out2 = tmp_path / "twin2"
    rc = main(["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model",
               str(tmp_path / "m"), "--string", str(case), "--components",
               str(EXAMPLES / "components.csv"), *sets, "--out", str(out2)])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "--string" in err
    assert not out2.exists()


def test_surface_channels_the_model_does_not_use_are_ignored() -> None:
    from drillfatigue.config.surrogate import DEFAULT_FEATURES

    cfg = TINY.model_copy(update={"features": tuple(f for f in DEFAULT_FEATURES
                                                    if f != "operation.wob_N")})
    no_wob = open_domain(fit_surrogate(make_synthetic_dataset(20, seed=5), cfg))
    log = pd.read_csv(EXAMPLES / "operating_log.csv").assign(standpipe_pressure_psi=3000.0)
    res = replay_log(log, _components(), no_wob, CONSTANTS)
    assert set(res.ignored_channels) == {"wob_kN", "standpipe_pressure_psi"}
    assert (res.components["damage"] > 0).all()
    # an unknown column that is no usual surface channel is still an error
    with pytest.raises(InputError, match="rpmm"):
        replay_log(log.rename(columns={"rpm": "rpmm"}), _components(), no_wob, CONSTANTS)


def test_survey_geometry_features_reach_the_model() -> None:
    """A model using inclination features gets, from the survey, the same values
    position_features gives for each component (bit at the log's depth)."""
    from drillfatigue.well.features import position_features

    survey = pd.read_csv(EXAMPLES / "survey.csv")
    cols = ("local_inc_deg", "bit_inc_deg", "build_to_bit_deg_per_30m")

    def geometry(md: np.ndarray, bit: np.ndarray) -> dict[str, np.ndarray]:
        return position_features(survey["md_m"], survey["dls_deg_per_30m"], survey["inc_deg"],
                                 md, bit, cols)

    data = make_synthetic_dataset(30, seed=4)
    md = data["md_m"].to_numpy()
    data = data.assign(**geometry(md, md + data["s_from_bit_m"].to_numpy()))
    cfg = TINY.model_copy(update={"features": TINY.features + cols})
    geo_model = open_domain(fit_surrogate(data, cfg))
    log = pd.DataFrame({"time_s": [0.0, 3600.0], "bit_md_m": 800.0, "rpm": 130.0,
                        "wob_kN": 90.0, "rop_m_per_h": 15.0})
    consts = {k: v for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"}
    comps = _components()
    res = replay_log(log, comps, geo_model, consts, survey).components
    s = comps["s_from_bit_m"].to_numpy()
    frame = pd.DataFrame({
        "operation.rpm": 130.0, "operation.wob_N": 90e3, "operation.rop_m_per_s": 15 / 3600,
        "friction.mu_static": 0.35, "friction.mu_dynamic": 0.28,
        "operation.mud_density_kg_per_m3": 1250.0, "bit.amplitude_m": 1e-3, "bit.lobes": 3.0,
        "well.kop_m": 500.0, "well.dls_deg_per_30m": 5.0, "well.profile": "build_hold",
        "s_from_bit_m": s, "md_m": 800.0 - s, "component_type": comps["component_type"],
        "location": comps["location"],
        **geometry(800.0 - s, np.full(s.shape, 800.0)),
        "local_dls_deg_per_30m": position_features(survey["md_m"], survey["dls_deg_per_30m"],
                                                   None, 800.0 - s, np.full(s.shape, 800.0),
                                                   ("local_dls_deg_per_30m",))[
                                                       "local_dls_deg_per_30m"]})
    p = geo_model.predict(frame, refuse=False)
    # float32 network, batch-size dependent round-off: 1e-5 relative (see above)
    np.testing.assert_allclose(res["damage"], p["damage_rate_per_h"] * 1.0, rtol=1e-5)
    with pytest.raises(InputError, match="inc_deg"):
        replay_log(log, comps, geo_model, consts, survey.drop(columns="inc_deg"))


def test_log_beyond_td_or_backwards_rpm_is_an_input_error(model: Surrogate) -> None:
    """A bit below the survey's last MD, or a string turning backwards, is no log a rig
    writes: an input error naming the channel and its range, not 1e35 damage."""
    survey = pd.read_csv(EXAMPLES / "survey.csv")  # last station at MD 3000 m
    log = pd.DataFrame({"time_s": [0.0, 60.0, 120.0], "bit_md_m": [1200.0, 1201.0, 4720.0],
                        "rpm": 120.0, "wob_kN": 80.0, "rop_m_per_h": 10.0})
    consts = {k: v for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"}
    with pytest.raises(InputError, match=r"bit_md_m: 4720 m at row 3 of the log is beyond "
                                         r"the well's total depth 3000 m"):
        replay_log(log, _components(), model, consts, survey)
    log.loc[2, "bit_md_m"] = 1202.0
    log.loc[1, "rpm"] = -120.0
    with pytest.raises(InputError, match=r"rpm: -120 is outside the physical range \(row 2\) "
                                         r"\(allowed: 0 <= rpm <= 1000\)"):
        replay_log(log, _components(), model, consts, survey)
    log.loc[1, "rpm"] = 120.0
    log["bit_md_m"] = [1.0e5, 1.0e5, 1.0e5]
    with pytest.raises(InputError, match=r"bit_md_m: 100000 is outside the physical range"):
        replay_log(log, _components(), model, consts)


def test_cli_replay_out_with_a_users_file(model: Surrogate, tmp_path: Path, capsys) -> None:
    """`twin replay --out DIR` with a user's file: refused before the replay, one line,
    exit 2, the file survives; a rerun into its own folder keeps a file added beside."""
    model.save(tmp_path / "m", export=False)
    sets = [a for k, v in CONSTANTS.items() if k != "local_dls_deg_per_30m"
            for a in ("--set", f"{k}={v}")]
    argv = ["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model",
            str(tmp_path / "m"), "--components", str(EXAMPLES / "components.csv"), "--survey",
            str(EXAMPLES / "survey.csv"), *sets, "--out"]
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "summary.json").write_text('{"mine": true}')
    assert main([*argv, str(mine)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and err.count("\n") == 1
    assert (mine / "summary.json").read_text() == '{"mine": true}'
    assert [p.name for p in mine.iterdir()] == ["summary.json"]
    out = tmp_path / "twin"
    assert main([*argv, str(out)]) == 0
    (out / "notes.txt").write_text("kept")
    assert main([*argv, str(out)]) == 0
    assert (out / "notes.txt").read_text() == "kept"
    assert (out / ".drillfatigue.json").is_file()


@pytest.fixture(scope="module")
def tiny_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A stand-in of the pipeline's model (params.yaml's features, lobe_amplitude_m)."""
    from testkit.tiny_surrogate import train_tiny_surrogate

    return train_tiny_surrogate(Path(__file__).resolve().parents[3] / "params.yaml",
                                tmp_path_factory.mktemp("tiny") / "model")


@pytest.mark.parametrize("setting, message", [
    ("lobe_amplitude_m=-1", "lobe_amplitude_m: -1 is outside the physical range "
                            "(allowed: 0 <= lobe_amplitude_m <= 0.05)"),
    ("lobe_amplitude_m=5", "lobe_amplitude_m: 5 is outside the physical range "
                           "(allowed: 0 <= lobe_amplitude_m <= 0.05)"),
    ("lobe_amplitude_mm=-1", "lobe_amplitude_mm: -1 is outside the physical range "
                             "(allowed: 0 <= lobe_amplitude_mm <= 50)"),
    ("mud_density_sg=-1.2", "mud_density_sg: -1.2 is outside the physical range "
                            "(allowed: 0 <= mud_density_sg <= 3)"),
])
def test_cli_set_constant_beyond_its_bound_exit_2(tiny_dir: Path, tmp_path: Path, capsys,
                                                  setting: str, message: str) -> None:
    """`twin --set lobe_amplitude_m=-1` (or 5) used to be replayed: the same one-line
    bounds error as every other entry point, exit 2, nothing written."""
    out = tmp_path / "twin"
    rc = main(["twin", "replay", str(EXAMPLES / "operating_log.csv"), "--model", str(tiny_dir),
               "--components", str(EXAMPLES / "components.csv"), "--set", setting,
               "--out", str(out)])
    assert rc == 2
    assert capsys.readouterr().err == f"error: {message}\n"
    assert not out.exists()


def test_hook_load_beyond_its_bound_is_an_input_error(model: Surrogate) -> None:
    log = pd.DataFrame({"time_s": [0.0, 60.0, 120.0], "bit_md_m": [1200.0, 1201.0, 1202.0],
                        "rpm": 120.0, "hook_load_kN": [900.0, -5.0, 900.0],
                        "rop_m_per_h": 10.0})
    consts = dict(CONSTANTS, off_bottom_hook_load_kN=1000.0)
    with pytest.raises(InputError, match=r"^hook_load_kN: -5 is outside the physical range "
                                         r"\(row 2\) \(allowed: 0 <= hook_load_kN <= 15000\)$"):
        replay_log(log, _components(), model, consts)
    log["hook_load_kN"] = 900.0
    with pytest.raises(InputError, match=r"^off_bottom_hook_load_klbf: 1e\+06 is outside"):
        replay_log(log, _components(), model, dict(CONSTANTS, off_bottom_hook_load_klbf=1e6))
