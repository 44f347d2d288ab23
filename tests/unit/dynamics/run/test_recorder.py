"""The run driver's parts, each alone: the recorder, the checkpoint, the running figures."""

from __future__ import annotations

import numpy as np
import pyarrow.parquet as pq
import pytest

from drillfatigue import rundir
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.checkpoint import load_checkpoint, save_checkpoint
from drillfatigue.dynamics.contact.events import RunningStats
from drillfatigue.dynamics.run.examples import uniform_chain_case
from drillfatigue.dynamics.run.model import build_model, straight_path
from drillfatigue.dynamics.run.recorder import Recorder
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder

JOINT_S = np.array([10.0, 20.0, 30.0])  # joints' distances from the bit (m)
SEL = np.array([0, 2], dtype=np.int64)


def _buffers(t0: float, n_rows: int = 3, n_seg: int = 4) -> tuple[np.ndarray, ...]:
    t = t0 + 0.01 * np.arange(n_rows)
    bl = np.zeros((n_rows, 1 + 6 * SEL.size))
    bl[:, 0] = t
    bl[:, 1:] = np.arange(6 * SEL.size)[None, :] + 100.0 * np.arange(n_rows)[:, None]
    bc = np.zeros((n_rows, 4 + L.N_CH))
    bc[:, 0] = t
    bc[:, 1 + L.H_BITMD] = 500.0 + t  # the bit MD moves with time
    bk = np.full((n_rows, 1 + 8 * n_seg), np.nan)
    bk[:, 0] = t
    bk[:, 1:1 + 8 * 3] = 1.0  # 3 active segments of 4 rows
    bk[:, 7::8] = 0.0  # normal force: none ...
    bk[:, 7] = 5.0  # ... but on segment 0
    return bl, bc, bk


def _seg(n_seg: int = 4) -> np.ndarray:
    seg = np.zeros((n_seg, L.N_SEG))
    seg[:, L.S_H] = 5.0
    return seg


def test_recorder_in_memory_keeps_loads_in_joint_order() -> None:
    rec = Recorder(JOINT_S, SEL, 4, None)
    for t0 in (0.0, 0.03):
        rec.write(rec.tables(*_buffers(t0), _seg(), 500.0))
    mem = rec.in_memory()
    assert mem["loads"].shape == (6, 2, 6)
    np.testing.assert_array_equal(mem["loads"][1, 1], np.arange(6, 12) + 100.0)
    np.testing.assert_allclose(mem["times_s"], 0.01 * np.arange(6))
    assert mem["kinematics"].num_rows == 6 * 3  # inactive rows dropped


def test_recorder_writes_final_files_only_for_a_complete_run(tmp_path) -> None:
    for status, name in (("complete", rundir.history_name), ("failed", rundir.partial_name)):
        folder = OutputFolder(tmp_path / status, rundir.KIND)
        rec = Recorder(JOINT_S, SEL, 4, folder)
        rec.start()
        rec.write(rec.tables(*_buffers(0.0), _seg(), 500.0))
        rec.close_part()
        rec.write(rec.tables(*_buffers(0.03), _seg(), 500.0))
        assert rec.finish(status)
        loads = pq.read_table(folder.path / name("loads")).to_pandas()
        assert len(loads) == 6 * SEL.size
        # md = bit MD (interpolated from the channels) - distance of the joint from the bit
        np.testing.assert_allclose(loads["md_m"], np.repeat(500.0 + 0.01 * np.arange(6), 2)
                                   - np.tile(JOINT_S[SEL], 6))
        contacts = pq.read_table(folder.path / name("contacts")).to_pandas()
        assert set(contacts["segment"]) == {0}
        other = rundir.partial_name if status == "complete" else rundir.history_name
        assert not (folder.path / other("loads")).exists()
    assert not (tmp_path / "complete" / rundir.PARTS).exists()  # parts removed
    assert list((tmp_path / "failed" / rundir.PARTS).glob("loads.*.parquet"))  # kept


def test_recorder_interrupted_keeps_parts_and_resumes_after_the_checkpoint(tmp_path) -> None:
    folder = OutputFolder(tmp_path / "run", rundir.KIND)
    rec = Recorder(JOINT_S, SEL, 4, folder)
    rec.start()
    rec.write(rec.tables(*_buffers(0.0), _seg(), 500.0))
    rec.close_part()  # a checkpoint after part 0
    rec.write(rec.tables(*_buffers(0.03), _seg(), 500.0))
    assert rec.finish("incomplete") == []
    assert not (folder.path / rundir.LOADS).exists()
    again = Recorder(JOINT_S, SEL, 4, OutputFolder(tmp_path / "run", rundir.KIND))
    again.resume_at(1)  # part 1 was written after the checkpoint: dropped
    assert [p.name for p in again.part_files("loads")] == ["loads.00000.parquet"]


def test_checkpoint_round_trip_restores_state_and_model_and_checks_the_case(tmp_path) -> None:
    cfg = uniform_chain_case(4, 40.0)
    model, state = build_model(cfg, straight_path(40.0))
    folder = OutputFolder(tmp_path / "run", rundir.KIND)
    state.v[:] = np.random.default_rng(1).normal(size=state.v.shape)
    model.seg[1, L.S_H] = 7.0
    saved = {k: a.copy() for k, a in state.arrays().items()}
    save_checkpoint(folder, {"hash": "abc", "part": 3}, model, state)
    fresh_model, fresh_state = build_model(cfg, straight_path(40.0))
    meta = load_checkpoint(folder, "abc", fresh_model, fresh_state)
    assert meta == {"hash": "abc", "part": 3}
    for k, a in fresh_state.arrays().items():
        np.testing.assert_array_equal(a, saved[k], err_msg=k)
    assert fresh_model.seg[1, L.S_H] == 7.0
    with pytest.raises(InputError, match="different configuration"):
        load_checkpoint(folder, "other", fresh_model, fresh_state)


def test_running_stats_resume_gives_the_same_figures() -> None:
    x = np.random.default_rng(2).normal(size=100)
    whole = RunningStats()
    whole.add("a", x)
    whole.n += x.size
    first = RunningStats()
    first.add("a", x[:40])
    first.n += 40
    resumed = RunningStats()
    resumed.load(first.state())
    resumed.add("a", x[40:])
    resumed.n += 60
    assert resumed.as_dict(resumed.n)["a"] == pytest.approx(whole.as_dict(whole.n)["a"], rel=1e-14)
