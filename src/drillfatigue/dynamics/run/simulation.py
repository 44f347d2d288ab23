"""Run a simulation and write the run directory.

``simulate(config, out_dir)`` builds the model (:mod:`drillfatigue.dynamics.run.model`),
advances it chunk by chunk with the numba integrator and writes, in
``out_dir``, the files of :mod:`drillfatigue.rundir` (loads, joints,
channels, kinematics, contacts, ``case.yaml`` and, last, ``summary.json``).
The driver :class:`Runner` delegates to three parts, each usable alone:
:class:`~drillfatigue.dynamics.run.recorder.Recorder` (histories in memory or as
Parquet parts), :mod:`~drillfatigue.dynamics.run.checkpoint` (save and resume) and
:mod:`~drillfatigue.dynamics.contact.events` (running statistics and the events of
the summary).

The summary's ``events`` (also copied to the top level for the dataset):
``stick_slip_severity`` ((max - min) / mean bit rpm over the window after the
rpm ramp), ``whirl_class`` (dominant class over the segments that orbit),
``whirl_per_segment``, ``bit_bounce_count``, ``max_contact_force_N``,
``rms_surface_torque_Nm``, ``peak_surface_torque_Nm``, ``contact_onset`` (per
segment in contact: time, bit MD and the segment's MD).

The run folder is claimed with :class:`drillfatigue.files.OutputFolder` (kind
``run``): a folder holding files this package did not write is refused before
any work, and a rerun replaces only the files of the earlier run. Histories
are written as parts (one per checkpoint interval) and become final files
only when the run completes; Ctrl-C leaves the parts and a summary that says
``incomplete``, and ``resume=True`` continues from the last checkpoint
(``checkpoint.npz``) with the same result as an uninterrupted run; a run that
diverges leaves its data as ``<name>.partial.parquet`` and a summary that
says ``failed``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import signal
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from importlib.metadata import version as package_version
from pathlib import Path
from typing import Any

import numba
import numpy as np
import pandas
import pyarrow as pa
import scipy
import yaml
from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

from drillfatigue import rundir
from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.top.setup import check_rig_setup
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.top import rig as rig_kernels
from drillfatigue.dynamics.run.buckling import BucklingTracker, detection_window_m
from drillfatigue.dynamics.core.bundles import new_records
from drillfatigue.dynamics.run.checkpoint import load_checkpoint, save_checkpoint
from drillfatigue.dynamics.contact.events import (
    EVENT_KEYS,
    RunningStats,
    classify_whirl,
    events_summary,
)
from drillfatigue.dynamics.step.integrator import advance, kinetic_energy
from drillfatigue.dynamics.run.model import (
    Model,
    State,
    WellPath,
    build_model,
    path_from_wellbore,
    raise_for_status,
    record_every,
)
from drillfatigue.dynamics.run.recorder import Recorder, write_table
from drillfatigue.dynamics.bit.rockface import ROP_FROM_WOB_MODELS, rop_slope_m_per_N_s
from drillfatigue.dynamics.core.status import OK as ST_OK
from drillfatigue.errors import InputError, SimulationError
from drillfatigue.limits import check_run_inputs
from drillfatigue.files import OutputFolder, atomic_write_json, atomic_write_text
from drillfatigue.well import build_wellbore

#: re-exported names of the run-directory format and the events
LOAD_COLUMNS = rundir.LOAD_COLUMNS
CHANNEL_COLUMNS = rundir.CHANNEL_COLUMNS
__all__ = ["CHANNEL_COLUMNS", "EVENT_KEYS", "LOAD_COLUMNS", "Runner", "SimulationResult",
           "classify_whirl", "config_hash", "simulate"]


@dataclass
class SimulationResult:
    """What a run produced.

    ``status`` is ``complete``, ``incomplete`` or ``failed``. With an ``out_dir``
    the histories are in its Parquet files; without one they are kept in memory:
    ``times_s`` (n_time,), ``loads`` (n_time, n_joint, 6) in the order of
    :data:`LOAD_COLUMNS`, ``channels`` (a dict of 1-D arrays incl. ``time_s``),
    ``span_bending`` (n_time, n_joint, 2) when ``contact.span_bending`` is on.
    """

    status: str
    summary: dict[str, Any]
    out_dir: Path | None
    model: Model
    state: State
    joints: np.ndarray
    times_s: np.ndarray | None = None
    loads: np.ndarray | None = None
    channels: dict[str, np.ndarray] = field(default_factory=dict)
    kinematics: Any = None
    span_bending: np.ndarray | None = None


def config_hash(config: CaseConfig) -> str:
    """SHA-256 of the canonical JSON of the resolved configuration."""
    data = config.model_dump(mode="json")
    if data.get("rig") is None:
        # cases without the rig section keep the hashes they had before it existed
        data.pop("rig", None)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _versions() -> dict[str, str]:
    return {"drillfatigue": package_version("drillfatigue"), "numpy": np.__version__,
            "numba": numba.__version__, "scipy": scipy.__version__, "pandas": pandas.__version__,
            "pyarrow": pa.__version__}


def _wellpath(config: CaseConfig) -> WellPath:
    radii = [c.outer_contact_radius_m for c in config.string.components]
    hole_r = min(h.diameter_m for h in config.well.hole) / 2.0
    clearance = max(hole_r - max(radii), 1e-3)
    return path_from_wellbore(build_wellbore(config.well, min_clearance_m=min(
        clearance, config.well.min_clearance_m)))


class RunFigures:
    """Running figures of a run from its channel rows: statistics of the summary
    channels, of the event window, and the largest energy-balance error."""

    def __init__(self, e0: float, t_window: float) -> None:
        self.stats = RunningStats()
        self.wstats = RunningStats()
        self.e0 = e0
        self.t_window = t_window
        self.energy_err_max = 0.0
        self.energy_ref = 1.0

    def add(self, bc: np.ndarray) -> None:
        """Fold channel rows (layout of :class:`bundles.Records`.buf_c) in."""
        if bc.shape[0] == 0:
            return
        for name, k in zip(("surface_torque_Nm", "hook_load_N", "wob_N", "bit_rpm"),
                           (L.H_TSURF, L.H_HOOK, L.H_WOB, L.H_BITRPM), strict=True):
            self.stats.add(name, bc[:, 1 + k])
        self.stats.n += bc.shape[0]
        win = bc[bc[:, 0] >= self.t_window - 1e-12]
        if win.shape[0]:
            for name, k in (("surface_torque_Nm", L.H_TSURF), ("bit_rpm", L.H_BITRPM)):
                self.wstats.add(name, win[:, 1 + k])
                self.wstats.add(name + "_sq", win[:, 1 + k] ** 2)
            self.wstats.n += win.shape[0]
        ke = bc[:, 1 + L.N_CH]
        e = ke + bc[:, 1 + L.H_PE] + bc[:, 1 + L.H_PG]
        bal = e - self.e0 - bc[:, 2 + L.N_CH] + bc[:, 3 + L.N_CH]
        self.energy_err_max = max(self.energy_err_max, float(np.abs(bal).max()))
        self.energy_ref = max(self.energy_ref, float((ke + np.abs(bc[:, 1 + L.H_PE])).max()),
                              float(np.abs(bc[:, 2 + L.N_CH]).max()))

    def state(self) -> dict[str, Any]:
        return {"stats": self.stats.state(), "wstats": self.wstats.state(), "e0": self.e0,
                "emax": self.energy_err_max, "eref": self.energy_ref}

    def load(self, meta: dict[str, Any]) -> None:
        self.stats.load(meta["stats"])
        self.wstats.load(meta["wstats"])
        self.e0 = float(meta["e0"])
        self.energy_err_max = float(meta["emax"])
        self.energy_ref = float(meta["eref"])


@contextlib.contextmanager
def _interrupt_after(deliver: bool = True) -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) until the block has finished, then raise KeyboardInterrupt.

    Around writing a checkpoint and the final files, so that an interrupt never
    leaves a half-renamed part or a checkpoint without its parts. Only in the
    main thread (elsewhere signals are not delivered to Python anyway). With
    ``deliver=False`` a Ctrl-C held over the block is dropped: around the final
    files of a complete run, where nothing is left to stop (every history is
    renamed and the summary says complete), it must not turn the run into an
    "interrupted" one.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught and deliver:
        raise KeyboardInterrupt


def check_rig(config: CaseConfig) -> dict[str, float]:
    """:func:`drillfatigue.dynamics.top.setup.check_rig_setup` of a case's rig section (one-line
    :class:`InputError` on a bad set-up); the autodriller loop's figures, or ``{}``."""
    rig = config.rig
    if rig is None:
        return {}
    c_rop = 0.0
    if rig.block_mode == "autodriller" and config.bit.model in ROP_FROM_WOB_MODELS:
        c_rop = rop_slope_m_per_N_s(config.bit, rig.effective_autodriller.wob_set_N,
                                    abs(config.operation.rpm))
    return check_rig_setup(rig, config, c_rop)


#: start-up left out of the drilling-window figures of summary.json, s
RIG_WINDOW_SKIP_S = 10.0


class RigFigures:
    """Streaming drilling-window figures of the rig boundaries from channel rows (the same
    definitions as :func:`drillfatigue.dynamics.top.rig.drilling_window_metrics`, rows equally
    spaced), and the start times of the connections."""

    def __init__(self, wob_set_N: float | None, travel_m: float, t_skip_s: float) -> None:
        self.wob_set = wob_set_N
        self.travel = travel_m
        self.t_skip = t_skip_s
        self.n = 0
        self.sums = {"on": 0.0, "wob": 0.0, "rop": 0.0, "tq": 0.0}
        self.bmin = math.inf
        self.bmax = -math.inf
        self.top_max = -math.inf
        self.phase = 0.0
        self.starts: list[float] = []

    def add(self, bc: np.ndarray) -> None:
        if bc.shape[0] == 0:
            return
        c = 4 + L.N_CH
        ph = bc[:, c + L.H_CONPH - L.N_CH]
        prev = np.r_[self.phase, ph[:-1]]
        self.starts += [float(t) for t in bc[(prev == 0.0) & (ph != 0.0), 0]]
        self.phase = float(ph[-1])
        blk = bc[:, c + L.H_BLOCK - L.N_CH]
        self.bmin = min(self.bmin, float(blk.min()))
        self.bmax = max(self.bmax, float(blk.max()))
        self.top_max = max(self.top_max, float(bc[:, c + L.H_TOPSTR - L.N_CH].max()))
        w = bc[bc[:, 0] >= self.t_skip - 1e-12]
        if w.shape[0] == 0:
            return
        self.n += w.shape[0]
        self.sums["on"] += float((w[:, 1 + L.H_WOB] > 0.0).sum())
        self.sums["wob"] += float(w[:, 1 + L.H_WOB].sum())
        self.sums["rop"] += float(w[:, 1 + L.H_ROP].sum())
        self.sums["tq"] += float(w[:, 1 + L.H_TSURF].sum())

    def summary(self) -> dict[str, Any]:
        out: dict[str, Any] = {"t_skip_s": self.t_skip, "block_min_m": self.bmin,
                               "block_max_m": self.bmax,
                               "block_within_travel": bool(self.bmin >= 0.0
                                                           and self.bmax <= self.travel),
                               "string_top_max_above_rotary_m": self.top_max,
                               "string_top_below_rotary": bool(self.top_max <= 0.0)}
        if self.n:
            m = {k: v / self.n for k, v in self.sums.items()}
            out.update(on_bottom_fraction=m["on"], mean_wob_N=m["wob"], mean_rop_m_per_s=m["rop"],
                       mean_surface_torque_Nm=m["tq"])
            if self.wob_set:
                out["wob_error_rel"] = m["wob"] / self.wob_set - 1.0
        return out

    def state(self) -> dict[str, Any]:
        return {"n": self.n, "sums": self.sums, "bmin": self.bmin, "bmax": self.bmax,
                "top_max": self.top_max, "phase": self.phase, "starts": self.starts}

    def load(self, d: dict[str, Any]) -> None:
        self.n, self.sums, self.bmin, self.bmax = d["n"], d["sums"], d["bmin"], d["bmax"]
        self.top_max, self.phase, self.starts = d["top_max"], d["phase"], d["starts"]


class Runner:
    """Drive one simulation: chunks of the integrator, recording, checkpoints, summary."""

    def __init__(self, config: CaseConfig, out_dir: Path | None, path: WellPath | None) -> None:
        self.config = config
        self.out_dir = out_dir
        self.path = path if path is not None else _wellpath(config)
        # the rig's set-up is checked before any step (build_model's relaxation takes steps)
        self.rig_check = check_rig(config)
        self.model, self.state = build_model(config, self.path)
        m = self.model
        check_run_inputs(config, float(self.path.node_md_m[-1]), m.dt)
        rec = config.recording
        n_j = m.n0 - 1
        if rec.joints is None:
            self.sel = np.arange(n_j, dtype=np.int64)
        else:
            bad = [j for j in rec.joints if not 0 <= j < n_j]
            if bad:
                raise InputError("recording.joints", f"joint index {bad[0]} does not exist",
                                 f"0 <= joint <= {n_j - 1}")
            self.sel = np.asarray(sorted(set(rec.joints)), dtype=np.int64)
        dt = m.dt
        self.every = [record_every(r, dt) for r in
                      (rec.loads_rate_hz, rec.channels_rate_hz, rec.kinematics_rate_hz)]
        self.n_steps_total = int(math.ceil(config.operation.duration_s / dt - 1e-9))
        self.chunk = int(config.solver.chunk_steps)
        ck = config.solver.checkpoint_every_s
        self.ck_steps = int(round(ck / dt)) if ck > 0 else 0
        self.start_step = int(round(rec.start_s / dt))
        self.figures = RunFigures(self._energy_now(), float(m.bp[L.B_TWIN]))
        self.rig_figures: RigFigures | None = None
        if config.rig is not None:
            ad = config.rig.effective_autodriller if config.rig.block_mode == "autodriller" \
                else None
            self.rig_figures = RigFigures(ad.wob_set_N if ad is not None else None,
                                          config.rig.block.travel_m, RIG_WINDOW_SKIP_S)
        self.buckling = self._buckling_tracker()
        self.hash = config_hash(config)
        self.wall_before = 0.0
        self.span_cut_samples = 0
        self.span_cut_spans = 0
        self.span_unsolved = 0
        self.folder: OutputFolder | None = None
        self.recorder = Recorder(m.segments.joint_s_from_bit_m, self.sel, m.n, None)

    def _energy_now(self) -> float:
        assert self.model.work is not None
        ch = self.model.work.ch
        return float(kinetic_energy(self.state.v, self.state.w, self.model.seg)
                     + ch[L.H_PE] + ch[L.H_PG])

    def _buckling_tracker(self) -> BucklingTracker | None:
        """The run's buckling detector, when ``recording.detect_buckling`` (default: with a rig
        section in a hole with a wall) asks for it."""
        on = self.config.recording.detect_buckling
        wall = self.path.wall
        if on is None:
            on = self.config.rig is not None
        if not on or wall.shape[0] == 0:
            return None
        seg = self.model.segments
        r_hole = float(wall[:, L.W_RAD].max())
        max_inc = float(np.arccos(np.clip(np.abs(self.path.node_tan[:, 2]), 0.0, 1.0)).max())
        window = detection_window_m(seg.ei_Nm2, seg.buoyed_weight_N / seg.length_m,
                                    r_hole - seg.contact_radius_m, seg.length_m, max_inc)
        return BucklingTracker(self.path.node_md_m, self.path.node_pos_m, self.path.node_tan,
                               wall, window)

    def _track_buckling(self, bc: np.ndarray, bk: np.ndarray) -> None:
        """Feed the kinematics samples of a chunk to the buckling detector."""
        tracker = self.buckling
        if tracker is None or bk.shape[0] == 0:
            return
        m = self.model
        n = m.n
        h = m.seg[:, L.S_H]
        s_mid = np.cumsum(np.r_[0.0, 2.0 * h[:-1]]) + h
        t = bk[:, 0]
        if bc.shape[0]:
            md_bit = np.interp(t, bc[:, 0], bc[:, 1 + L.H_BITMD])
        else:
            md_bit = np.full(t.size, float(self.state.sc[L.C_MDROCK]))
        kv = bk[:, 1:].reshape(t.size, n, 8)
        joints = m.segments.joint_s_from_bit_m
        for i in range(t.size):
            act = np.isfinite(kv[i, :, 0])
            tracker.add(float(t[i]), float(md_bit[i]), s_mid[act], kv[i, act, 0:3],
                        kv[i, act, 6], m.seg[act, L.S_RC], joints)

    def _rig_summary(self) -> dict[str, Any]:
        """The rig boundaries' set-up and what they did, for summary.json."""
        rig = self.config.rig
        assert rig is not None
        m, sc = self.model, self.state.sc
        out: dict[str, Any] = {"effective_inputs": rig.effective_inputs(), **m.rig_info}
        out.update(self.rig_check)
        rf = self.rig_figures
        assert rf is not None
        out["window"] = rf.summary()
        out["connections"] = {"stands_added": int(sc[L.C_NSTAND]), "start_times_s": rf.starts}
        out["block_travel_final_m"] = float(sc[L.C_BLK + rig_kernels.BS_X])
        return out

    # --- the run folder ---------------------------------------------------------------
    def _open_folder(self, resume: bool) -> bool:
        """Claim the run folder; restore the checkpoint when resuming. Returns whether resumed."""
        assert self.out_dir is not None
        folder = OutputFolder(self.out_dir, rundir.KIND, names=rundir.FILES)
        self.folder = folder
        self.recorder.folder = folder
        meta = load_checkpoint(folder, self.hash, self.model, self.state) if resume else None
        if meta is None:
            folder.remove_all_owned()
            self.recorder.start()
        else:
            self.recorder.resume_at(int(meta["part"]))
            self.figures.load(meta)
            if self.rig_figures is not None:
                self.rig_figures.load(meta["rig"])
            if self.buckling is not None:
                self.buckling.load(meta["buckling"])
            self.wall_before = float(meta["wall"])
        atomic_write_text(folder.file(rundir.CASE), yaml.safe_dump(
            self.config.model_dump(mode="json"), sort_keys=False))
        self._write_joints()
        return meta is not None

    def _checkpoint(self, wall: float) -> None:
        assert self.folder is not None
        self.recorder.close_part()
        meta = {"hash": self.hash, "part": self.recorder.part, "wall": wall,
                **self.figures.state()}
        if self.rig_figures is not None:
            meta["rig"] = self.rig_figures.state()
        if self.buckling is not None:
            meta["buckling"] = self.buckling.state()
        save_checkpoint(self.folder, meta, self.model, self.state)

    def _write_joints(self) -> None:
        assert self.folder is not None
        seg = self.model.segments
        comps = self.config.string.components
        j = self.sel
        names = [comps[c].name or f"{comps[c].type}{c}" for c in seg.joint_component[j]]
        tab = pa.table({
            "joint": j.astype(np.int32), "component": names,
            "component_type": [seg.joint_component_type[i] for i in j],
            "s_from_bit_m": seg.joint_s_from_bit_m[j], "body_od_m": seg.body_od_m[j],
            "body_id_m": seg.body_id_m[j], "conn_od_m": seg.conn_od_m[j],
            "conn_id_m": seg.conn_id_m[j]})
        write_table(self.folder, rundir.JOINTS, [tab])

    # --- main loop --------------------------------------------------------------------
    def run(self, progress: bool, resume: bool) -> SimulationResult:
        if self.out_dir is not None:
            self._open_folder(resume)
        m, s = self.model, self.state
        wk = m.work
        params = m.params
        rows = [self.chunk // e + 2 for e in self.every]
        rec0 = new_records(self.sel, tuple(self.every), tuple(rows), m.n, m.n_ch,
                           span=m.cpar[L.P_SPAN] != 0.0)
        status = "incomplete"
        error: SimulationError | None = None
        t_wall0 = time.perf_counter()
        bar = _Progress(self.n_steps_total * m.dt) if progress else None
        try:
            while True:
                step = int(s.sc[L.C_STEP])
                if step >= self.n_steps_total:
                    status = "complete"
                    break
                k = min(self.chunk, self.n_steps_total - step)
                if self.ck_steps:
                    k = min(k, self.ck_steps - step % self.ck_steps)
                # no recording before start_s: large 'every' values
                rec_on = step + k > self.start_step
                ev = self.every if rec_on else [10 ** 15] * 3
                rec = rec0._replace(every_l=ev[0], every_c=ev[1], every_k=ev[2])
                rec.counts[:] = 0
                st = advance(k, s, params, wk, rec)
                self.span_cut_samples += int(rec.counts[3])
                self.span_cut_spans += int(rec.counts[4])
                self.span_unsolved += int(rec.counts[5])
                bl = rec.buf_l[: rec.counts[0]]
                bc = rec.buf_c[: rec.counts[1]]
                bk = rec.buf_k[: rec.counts[2]]
                if rec_on and self.start_step > step:
                    t0 = self.start_step * m.dt - 0.5 * m.dt
                    bl, bc, bk = bl[bl[:, 0] >= t0], bc[bc[:, 0] >= t0], bk[bk[:, 0] >= t0]
                self.figures.add(bc)
                if self.rig_figures is not None:
                    self.rig_figures.add(bc)
                self._track_buckling(bc, bk)
                self.recorder.write(self.recorder.tables(bl, bc, bk, m.seg,
                                                         float(s.sc[L.C_MDROCK])))
                if st != ST_OK:
                    try:
                        raise_for_status(st, rec.info, m)
                    except SimulationError as exc:
                        error = exc
                    status = "failed"
                    break
                new_step = int(s.sc[L.C_STEP])
                if self.folder is not None and self.ck_steps and new_step % self.ck_steps == 0 \
                        and new_step < self.n_steps_total:
                    with _interrupt_after():
                        self._checkpoint(self.wall_before + time.perf_counter() - t_wall0)
                if bar is not None:
                    bar.update(new_step * m.dt, self.wall_before + time.perf_counter() - t_wall0)
        finally:
            if bar is not None:
                bar.close()
            wall = self.wall_before + time.perf_counter() - t_wall0
            # a Ctrl-C while a complete run writes its final files arrives after the
            # work is done: the run is reported complete (its summary says so)
            with _interrupt_after(deliver=status != "complete"):
                result = self._finish(status, wall, error)
        if error is not None:
            raise error
        return result

    def _finish(self, status: str, wall: float, error: SimulationError | None) -> SimulationResult:
        m = self.model
        sc = self.state.sc
        sim_t = float(sc[L.C_STEP]) * m.dt
        summary: dict[str, Any] = {
            "status": status,
            "config_hash": self.hash,
            "versions": _versions(),
            "wall_time_s": wall,
            "duration_s": sim_t,
            "duration_requested_s": self.config.operation.duration_s,
            "real_time_factor": sim_t / wall if wall > 0 else None,
            "dt_s": m.dt,
            "n_steps": int(sc[L.C_STEP]),
            "n_segments": m.n0,
            "n_joints_recorded": int(self.sel.size),
            "hook_load_setpoint_N": m.hook_load_N,
            "wob_initial_N": m.wob0_N,
            "neutral_point_s_from_bit_m": m.neutral_point_s_from_bit_m,
            "top_segment_length_m": m.top_length_m,
            "figures": self.figures.stats.as_dict(self.figures.stats.n),
            "energy_balance_error_J": self.figures.energy_err_max,
            "energy_balance_error_rel": self.figures.energy_err_max / self.figures.energy_ref,
            "work_in_J": float(sc[L.C_WIN]),
            "dissipated_J": float(sc[L.C_DISS]),
            "n_segments_initial": m.n0,
            "n_segments_final": self.state.n_active,
            "segments_added": int(sc[L.C_NSPLIT]),
            "segments_merged": int(sc[L.C_NMERGE]),
            "bit_md_final_m": float(sc[L.C_MDROCK]),
            "trip_out_stopped_at_minimum": bool(sc[L.C_GUARD] == 1.0),
        }
        if m.cpar[L.P_SPAN] != 0.0:
            # loads samples (since this process started the run) with spans in compression
            # beyond their Euler load, and the number of such spans over those samples:
            # those spans got no correction, the chain was cut there (span_record)
            summary["span_bending_buckled_samples"] = self.span_cut_samples
            summary["span_bending_buckled_spans"] = self.span_cut_spans
            # samples with no span solved at all (recorded as zero at every joint)
            summary["span_bending_unsolved_samples"] = self.span_unsolved
        if error is not None:
            summary["message"] = str(error)
        if m.rig_on:
            summary["rig"] = self._rig_summary()
        if self.buckling is not None:
            summary["buckling"] = self.buckling.summary()
        ev = events_summary(m.seg, m.bp, sc, self.state.cst, self.figures.wstats)
        summary["events"] = ev
        for k in EVENT_KEYS:
            summary[k] = ev[k]
        res = SimulationResult(status=status, summary=summary, out_dir=self.out_dir, model=m,
                               state=self.state, joints=self.sel)
        if self.folder is None:
            mem = self.recorder.in_memory()
            res.times_s, res.loads = mem["times_s"], mem["loads"]
            res.span_bending = mem.get("span_bending")
            res.channels, res.kinematics = mem["channels"], mem["kinematics"]
            return res
        written = self.recorder.finish(status)
        if status == "complete":
            self.folder.remove([rundir.CHECKPOINT])
        elif status == "incomplete":
            summary["message"] = ("interrupted: the histories so far are in "
                                  f"{rundir.PARTS}/; continue with --resume")
        summary["files"] = written
        atomic_write_json(self.folder.file(rundir.SUMMARY), summary)
        return res


class _Progress:
    """rich progress bar: simulated time, real-time factor, ETA."""

    def __init__(self, total_s: float) -> None:
        self.p = Progress(TextColumn("simulate"), BarColumn(),
                          TextColumn("{task.completed:.2f}/{task.total:.2f} s sim"),
                          TextColumn("{task.fields[rtf]}"), TimeRemainingColumn(),
                          transient=False)
        self.p.start()
        self.task = self.p.add_task("sim", total=total_s, rtf="")

    def update(self, sim_t: float, wall: float) -> None:
        rtf = sim_t / wall if wall > 0 else 0.0
        self.p.update(self.task, completed=sim_t, rtf=f"{rtf:.3g}x real time")

    def close(self) -> None:
        self.p.stop()


def simulate(config: CaseConfig, out_dir: Path | None = None, *, progress: bool = True,
             resume: bool = False, path: WellPath | None = None) -> SimulationResult:
    """Run one simulation case.

    Parameters
    ----------
    config : CaseConfig
        Validated case (well, string, operation, solver, recording, ...).
    out_dir : Path, optional
        Run directory; without it the histories are returned in memory. A new
        or empty folder, or one this package wrote as a run folder.
    progress : bool
        Show a rich progress bar (simulated time, real-time factor, ETA).
    resume : bool
        Continue from ``out_dir/checkpoint.npz`` (same configuration required).
    path : WellPath, optional
        Use this well centre line instead of building ``config.well``.

    Returns
    -------
    SimulationResult

    Raises
    ------
    SimulationError
        The integration diverged (the run directory is marked ``failed``).
    InputError
        Inconsistent inputs (string longer than the hole, bad joint index...), or
        an ``out_dir`` that holds files this package did not write.
    KeyboardInterrupt
        Ctrl-C; the run directory is marked ``incomplete`` and can be resumed.
    """
    if out_dir is not None:
        OutputFolder.check(out_dir, rundir.KIND, names=rundir.FILES)
    runner = Runner(config, Path(out_dir) if out_dir is not None else None, path)
    return runner.run(progress=progress, resume=resume)
