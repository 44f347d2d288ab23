"""Operating-window map (``drillfatigue.surrogate.window``, ``drillfatigue window``)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pandas as pd
import pytest

from drillfatigue.cli import main
from drillfatigue.errors import InputError
from drillfatigue.surrogate import Surrogate
from drillfatigue.surrogate.window import Axis, operating_window, window_figure

from testkit.service_helpers import CONDITION, EXAMPLES, synthetic_model

FIXED = {k: v for k, v in CONDITION.items() if k not in ("rpm", "wob_kN")}
RTOL = 1e-5  # float32 batch round-off, see test_service.py


@pytest.fixture(scope="module")
def model() -> Surrogate:
    return synthetic_model()


def test_grid_node_is_the_plain_prediction_in_si(model: Surrogate) -> None:
    x = Axis.linear("rpm", 20.0, 220.0, 9)
    y = Axis.linear("rop_m_per_h", 2.0, 80.0, 5)
    fixed = {**FIXED, "wob_kN": 80.0}
    fixed.pop("rop_m_per_h")
    w = operating_window(model, x, y, fixed)
    assert w.life_h.shape == (5, 9)
    # independent reference: the SI rows written out by hand, one per node
    rows = []
    for rop in y.values:
        for rpm in x.values:
            rows.append({"operation.rpm": rpm, "operation.wob_N": 80e3,
                         "operation.rop_m_per_s": rop / 3600.0, "friction.mu_static": 0.35,
                         "friction.mu_dynamic": 0.28, "operation.mud_density_kg_per_m3": 1250.0,
                         "bit.amplitude_m": 1e-3, "bit.lobes": 3.0, "well.kop_m": 500.0,
                         "well.dls_deg_per_30m": 5.0, "md_m": 1400.0, "s_from_bit_m": 40.0,
                         "local_dls_deg_per_30m": 0.0, "component_type": "collar",
                         "location": "connection", "well.profile": "build_hold"})
    ref = model.predict(pd.DataFrame(rows))  # out of domain: no number, in both
    np.testing.assert_allclose(w.life_h.ravel(), ref["life_h"], rtol=RTOL)
    np.testing.assert_allclose(w.life_h_lower.ravel(), ref["life_h_lower"], rtol=RTOL)
    assert np.all(np.isnan(w.life_h[w.ood]))
    np.testing.assert_array_equal(w.ood.ravel(), ref["ood"].to_numpy(dtype=bool))
    # rpm 20 and 220 are outside the training range: those columns are flagged
    assert w.ood[:, 0].all() and w.ood[:, -1].all()
    best = w.best_in_domain()
    inside = np.where(w.ood, -np.inf, w.life_h_lower)
    i, j = np.unravel_index(np.argmax(inside), inside.shape)
    assert best == {"rpm": x.values[j], "rop_m_per_h": y.values[i],
                    "life_h": w.life_h[i, j], "life_h_lower": w.life_h_lower[i, j]}
    frame = w.to_frame()
    assert len(frame) == 45 and frame["ood"].sum() == w.ood.sum()


def test_out_of_domain_cells_are_hatched(model: Surrogate) -> None:
    w = operating_window(model, Axis.linear("rpm", 0.0, 260.0, 14),
                         Axis.linear("wob_kN", 0.0, 260.0, 12), FIXED)
    fig = window_figure(w)
    hatched = [c for c in fig.axes[0].collections if c.get_hatch() == "///"]
    assert len(hatched) == 1
    assert len(hatched[0].get_paths()) == int(w.ood.sum()) > 0
    assert 0 < w.ood.sum() < w.ood.size


def test_survey_gives_the_geometry_at_the_location(model: Surrogate) -> None:
    survey = pd.read_csv(EXAMPLES / "survey.csv")
    fixed = {k: v for k, v in FIXED.items() if k != "local_dls_deg_per_30m"}
    fixed.update(md_m=700.0, s_from_bit_m=8.0)
    w = operating_window(model, Axis.linear("rpm", 60, 180, 3),
                         Axis.linear("wob_kN", 40, 160, 3), fixed, survey)
    # 700 m lies in the 5 deg/30 m build from the KOP at 500 m (data/examples/survey.csv)
    dls = float(np.interp(700.0, survey["md_m"], survey["dls_deg_per_30m"]))
    assert w.fixed["local_dls_deg_per_30m"] == pytest.approx(dls, rel=1e-12)
    direct = operating_window(model, Axis.linear("rpm", 60, 180, 3),
                              Axis.linear("wob_kN", 40, 160, 3),
                              {**fixed, "local_dls_deg_per_30m": dls})
    np.testing.assert_allclose(w.life_h, direct.life_h, rtol=RTOL)
    with pytest.raises(InputError, match="survey"):
        operating_window(model, Axis.linear("rpm", 60, 180, 3),
                         Axis.linear("wob_kN", 40, 160, 3), FIXED, survey)


@pytest.mark.parametrize("spec, problem", [
    ("rpm", "no '='"), ("rpm=1:2", "START:STOP:NODES"), ("rpm=a:2:3", "non-numeric"),
    ("rpm=5:2:3", "not above start"), ("rpm=1:2:1", "got 1"), ("rpm=1:2:401", "got 401")])
def test_axis_spec_errors(spec: str, problem: str) -> None:
    with pytest.raises(InputError, match=problem):
        Axis.parse(spec, "--x")


def test_axis_beyond_a_physical_bound_is_an_input_error(model: Surrogate) -> None:
    """rpm -10 on an axis used to be mapped (and hatched as out of domain)."""
    with pytest.raises(InputError) as e:
        operating_window(model, Axis.linear("rpm", -10, 200, 5, "x"),
                         Axis.linear("wob_kN", 20, 200, 5, "y"), FIXED)
    assert str(e.value) == ("x.start: -10 is outside the physical range "
                            "(allowed: 0 <= rpm <= 1000)")
    with pytest.raises(InputError, match=r"^y\.stop: 1200 is outside the physical range "
                                         r"\(allowed: 0 <= wob_kN <= 1000\)$"):
        operating_window(model, Axis.linear("rpm", 40, 200, 5, "x"),
                         Axis.linear("wob_kN", 20, 1200, 5, "y"), FIXED)


def test_cli_writes_png_and_csv(model: Surrogate, tmp_path: Path, capsys) -> None:
    model.save(tmp_path / "m", export=False)
    out, csv = tmp_path / "maps" / "window.png", tmp_path / "maps" / "grid.csv"
    args = ["window", "--model", str(tmp_path / "m"), "--x", "rpm=40:200:17",
            "--y", "wob_kN=20:200:10", "--out", str(out), "--out-csv", str(csv)]
    for k, v in FIXED.items():
        args += ["--set", f"{k}={v}"]
    assert main(args) == 0
    img = mpimg.imread(out)
    assert img.shape[0] > 300 and img.shape[1] > 500
    grid = pd.read_csv(csv)
    assert len(grid) == 170 and list(grid.columns[:2]) == ["rpm", "wob_kN"]
    assert "longest life in domain" in capsys.readouterr().out
    assert sorted(p.name for p in out.parent.iterdir()) == ["grid.csv", "window.png"]


@pytest.mark.parametrize("change, field", [
    (["--x", "torque=1:2:3"], "x.name"),
    (["--y", "location=0:1:3"], "y.name"),
    (["--out", "map.jpg"], "--out"),
    (["--set", "rpm=100"], "rpm"),
    (["--set", "mu_static"], "--set"),
    # a value no rig can have on an axis is the one-line bounds error, not a hatched cell
    (["--x", "rpm=-10:200:5"], "--x: -10 is outside the physical range (allowed: 0 <= rpm "
                               "<= 1000)"),
    (["--y", "wob_klbf=10:300:5"], "--y: 300 is outside the physical range (allowed: 0 <= "
                                   "wob_klbf <= 224.809)"),
])
def test_cli_bad_input_exit_2_nothing_written(model: Surrogate, tmp_path: Path, capsys,
                                              change: list[str], field: str) -> None:
    model.save(tmp_path / "m", export=False)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    args = ["window", "--model", str(tmp_path / "m"), "--out", str(out_dir / "map.png")]
    for k, v in FIXED.items():
        args += ["--set", f"{k}={v}"]
    if change[0] == "--out":
        args[args.index("--out") + 1] = str(out_dir / change[1])
    else:
        args += change
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {field}") and err.count("\n") == 1, err
    assert list(out_dir.iterdir()) == []


def test_cli_grid_csv_never_replaces_the_survey_it_reads(model: Surrogate, tmp_path: Path,
                                                         capsys) -> None:
    """--out-csv naming the --survey file would replace the survey by the grid: refused, one
    line, exit 2, the survey and the folder unchanged."""
    model.save(tmp_path / "m", export=False)
    survey = tmp_path / "survey.csv"
    survey.write_text("md_m,dls_deg_per_30m,inc_deg\n0,0,0\n2000,3,40\n")
    text = survey.read_text()
    args = ["window", "--model", str(tmp_path / "m"), "--out", str(tmp_path / "map.png"),
            "--survey", str(survey), "--out-csv", str(survey)]
    for k, v in FIXED.items():
        args += ["--set", f"{k}={v}"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out-csv:") and "--survey" in err and err.count("\n") == 1, err
    assert survey.read_text() == text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m", "survey.csv"]
