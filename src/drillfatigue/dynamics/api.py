"""Run a simulation and write the run directory.

``simulate(config, out_dir)`` builds the model (:mod:`drillfatigue.dynamics.model`),
advances it chunk by chunk with the numba integrator, streams the recorded
histories to Parquet and writes, in ``out_dir``:

``loads.parquet``
    One row per (time, joint): ``time_s, joint, md_m, axial_N, shear_x_N,
    shear_y_N, bending_x_Nm, bending_y_Nm, torque_Nm`` (joint frame, z along the
    pipe axis pointing downhole; axial > 0 in tension; loads the upper part
    exerts on the lower part).
``joints.parquet``
    One row per recorded joint: ``joint, component, component_type,
    s_from_bit_m, body_od_m, body_id_m, conn_od_m, conn_id_m``.
``channels.parquet``
    ``time_s, surface_torque_Nm, hook_load_N, wob_N, tob_Nm, top_rpm, bit_rpm,
    bit_md_m, rop_m_per_s`` and the energy terms.
``kinematics.parquet``
    ``time_s, segment, s_from_bit_m, x_m, y_m, z_m, vx_m_per_s, vy_m_per_s, vz_m_per_s,
    normal_N, dist_from_centre_m`` (active segments only; segments added by drilling
    appear when they are created).
``contacts.parquet``
    The compact contact history, at the kinematics rate: one row per (time,
    segment in wall contact): ``time_s, segment, normal_N`` (sum over the
    segment's contact points), ``dist_from_centre_m`` (largest distance of its
    contact points from the hole centre line).
``case.yaml``, ``summary.json`` (written last). The summary's ``events`` (also
copied to the top level for the dataset): ``stick_slip_severity`` ((max - min) /
mean bit rpm over the window after the rpm ramp), ``whirl_class`` (dominant
class over the segments that orbit), ``whirl_per_segment``, ``bit_bounce_count``,
``max_contact_force_N``, ``rms_surface_torque_Nm``, ``peak_surface_torque_Nm``,
``contact_onset`` (per segment in contact: time, bit MD and the segment's MD).

Histories are written as parts (one Parquet file per checkpoint interval, in
``.parts/``) and merged into the final files at the end; every file is written
to a temporary name and renamed. Ctrl-C leaves a valid run directory whose
summary says ``incomplete``; ``resume=True`` continues from the last checkpoint
(``checkpoint.npz``) and gives the same result as an uninterrupted run.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import yaml

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics import layout as L
from drillfatigue.dynamics.bundles import new_records
from drillfatigue.dynamics.integrator import advance, kinetic_energy
from drillfatigue.dynamics.model import (
    Model,
    State,
    WellPath,
    build_model,
    path_from_wellbore,
    raise_for_status,
)
from drillfatigue.dynamics.status import OK as ST_OK
from drillfatigue.errors import InputError, SimulationError

LOAD_COLUMNS = ("axial_N", "shear_x_N", "shear_y_N", "bending_x_Nm", "bending_y_Nm", "torque_Nm")
CHANNEL_COLUMNS = ("surface_torque_Nm", "hook_load_N", "wob_N", "tob_Nm", "top_rpm", "bit_rpm",
                   "bit_md_m", "rop_m_per_s")
_CH_INDEX = (L.H_TSURF, L.H_HOOK, L.H_WOB, L.H_TOB, L.H_TOPRPM, L.H_BITRPM, L.H_BITMD, L.H_ROP)
FILES = ("loads", "channels", "kinematics", "contacts")


@dataclass
class SimulationResult:
    """What a run produced.

    ``status`` is ``complete``, ``incomplete`` or ``failed``. With an ``out_dir``
    the histories are in its Parquet files; without one they are kept in memory:
    ``times_s`` (n_time,), ``loads`` (n_time, n_joint, 6) in the order of
    :data:`LOAD_COLUMNS`, ``channels`` (a dict of 1-D arrays incl. ``time_s``).
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
    kinematics: np.ndarray | None = None


def config_hash(config: CaseConfig) -> str:
    """SHA-256 of the canonical JSON of the resolved configuration."""
    text = json.dumps(config.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _versions() -> dict[str, str]:
    import numba
    import pandas
    import scipy

    import drillfatigue
    return {"drillfatigue": drillfatigue.__version__, "numpy": np.__version__,
            "numba": numba.__version__, "scipy": scipy.__version__, "pandas": pandas.__version__,
            "pyarrow": pa.__version__}


def _atomic_write_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def _wellpath(config: CaseConfig) -> WellPath:
    from drillfatigue.well import build_wellbore

    radii = [c.outer_contact_radius_m for c in config.string.components]
    hole_r = min(h.diameter_m for h in config.well.hole) / 2.0
    clearance = max(hole_r - max(radii), 1e-3)
    return path_from_wellbore(build_wellbore(config.well, min_clearance_m=min(
        clearance, config.well.min_clearance_m)))


class _Stats:
    """Streaming mean / min / max of the summary channels."""

    def __init__(self) -> None:
        self.n = 0
        self.s: dict[str, float] = {}
        self.lo: dict[str, float] = {}
        self.hi: dict[str, float] = {}

    def add(self, name: str, x: np.ndarray) -> None:
        if x.size == 0:
            return
        self.s[name] = self.s.get(name, 0.0) + float(x.sum())
        self.lo[name] = min(self.lo.get(name, math.inf), float(x.min()))
        self.hi[name] = max(self.hi.get(name, -math.inf), float(x.max()))

    def as_dict(self, n: int) -> dict[str, dict[str, float]]:
        return {k: {"mean": self.s[k] / max(n, 1), "min": self.lo[k], "max": self.hi[k]}
                for k in self.s}

    def state(self) -> dict[str, Any]:
        return {"n": self.n, "s": self.s, "lo": self.lo, "hi": self.hi}

    def load(self, d: dict[str, Any]) -> None:
        self.n, self.s, self.lo, self.hi = d["n"], d["s"], d["lo"], d["hi"]


class Runner:
    """Drive one simulation: chunks, recording, checkpoints, outputs."""

    def __init__(self, config: CaseConfig, out_dir: Path | None, path: WellPath | None) -> None:
        self.config = config
        self.out_dir = out_dir
        self.path = path if path is not None else _wellpath(config)
        self.model, self.state = build_model(config, self.path)
        m = self.model
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
        self.every = [max(1, round(1.0 / (r * dt))) for r in
                      (rec.loads_rate_hz, rec.channels_rate_hz, rec.kinematics_rate_hz)]
        self.n_steps_total = int(math.ceil(config.operation.duration_s / dt - 1e-9))
        self.chunk = int(config.solver.chunk_steps)
        ck = config.solver.checkpoint_every_s
        self.ck_steps = int(round(ck / dt)) if ck > 0 else 0
        self.start_step = int(round(rec.start_s / dt))
        self.stats = _Stats()
        self.wstats = _Stats()
        self.t_window = float(m.bp[L.B_TWIN])
        self.e0 = self._energy_now()
        self.energy_err_max = 0.0
        self.energy_ref = 1.0
        self.part = 0
        self.writers: dict[str, pq.ParquetWriter] = {}
        self.mem: dict[str, list[np.ndarray]] = {k: [] for k in FILES}
        self.hash = config_hash(config)
        self.wall_before = 0.0

    # --- energy -------------------------------------------------------------------------
    def _energy_now(self) -> float:
        ch = self.model.work.ch
        return float(kinetic_energy(self.state.v, self.state.w, self.model.seg)
                     + ch[L.H_PE] + ch[L.H_PG])

    # --- parts ----------------------------------------------------------------------------
    def _parts_dir(self) -> Path:
        assert self.out_dir is not None
        return self.out_dir / ".parts"

    def _tables(self, bl: np.ndarray, bc: np.ndarray, bk: np.ndarray) -> dict[str, pa.Table]:
        m = self.model
        seg = m.segments
        out: dict[str, pa.Table] = {}
        nsel = self.sel.size
        if bl.shape[0]:
            t = bl[:, 0]
            ld = bl[:, 1:].reshape(bl.shape[0], nsel, 6)
            if bc.shape[0]:
                md_bit = np.interp(t, bc[:, 0], bc[:, 1 + L.H_BITMD])
            else:
                md_bit = float(self.state.sc[L.C_MDROCK]) + 0.0 * t
            cols: dict[str, Any] = {
                "time_s": np.repeat(t, nsel),
                "joint": np.tile(self.sel, t.size).astype(np.int32),
                "md_m": (md_bit[:, None] - seg.joint_s_from_bit_m[self.sel][None, :]).ravel(),
            }
            for k, name in enumerate(LOAD_COLUMNS):
                cols[name] = ld[:, :, k].ravel()
            out["loads"] = pa.table(cols)
        if bc.shape[0]:
            cols = {"time_s": bc[:, 0]}
            for name, k in zip(CHANNEL_COLUMNS, _CH_INDEX, strict=True):
                cols[name] = bc[:, 1 + k]
            cols["kinetic_energy_J"] = bc[:, 1 + L.N_CH]
            cols["potential_energy_J"] = bc[:, 1 + L.H_PE] + bc[:, 1 + L.H_PG]
            cols["work_in_J"] = bc[:, 2 + L.N_CH]
            cols["dissipated_J"] = bc[:, 3 + L.N_CH]
            cols["segments_in_contact"] = bc[:, 1 + L.H_NCON]
            cols["max_contact_force_N"] = bc[:, 1 + L.H_FCMAX]
            cols["n_segments"] = bc[:, 1 + L.H_NSEG]
            out["channels"] = pa.table(cols)
        if bk.shape[0]:
            n = m.n
            t = bk[:, 0]
            kv = bk[:, 1:].reshape(t.size, n, 8)
            h = m.seg[:, L.S_H]
            s_mid = np.cumsum(np.r_[0.0, 2.0 * h[:-1]]) + h
            tt = np.repeat(t, n)
            sg = np.tile(np.arange(n, dtype=np.int32), t.size)
            flat = kv.reshape(-1, 8)
            act = np.isfinite(flat[:, 0])
            cols = {"time_s": tt[act], "segment": sg[act], "s_from_bit_m": np.tile(s_mid, t.size)[act]}
            for k, name in enumerate(("x_m", "y_m", "z_m", "vx_m_per_s", "vy_m_per_s", "vz_m_per_s",
                                      "normal_N", "dist_from_centre_m")):
                cols[name] = flat[act, k]
            out["kinematics"] = pa.table(cols)
            con = act & (np.nan_to_num(flat[:, 6]) > 0.0)
            out["contacts"] = pa.table({"time_s": tt[con], "segment": sg[con],
                                        "normal_N": flat[con, 6],
                                        "dist_from_centre_m": flat[con, 7]})
        return out

    def _write(self, tables: dict[str, pa.Table]) -> None:
        if self.out_dir is None:
            for k, tab in tables.items():
                self.mem[k].append(tab)
            return
        for k, tab in tables.items():
            w = self.writers.get(k)
            if w is None:
                p = self._parts_dir() / f"{k}.{self.part:05d}.parquet.open"
                w = pq.ParquetWriter(p, tab.schema)
                self.writers[k] = w
            w.write_table(tab)

    def _close_part(self) -> None:
        """Close the open part files (they become final parts)."""
        if self.out_dir is None:
            return
        for k, w in self.writers.items():
            w.close()
            p = self._parts_dir() / f"{k}.{self.part:05d}.parquet.open"
            os.replace(p, p.with_suffix(""))
        self.writers = {}
        self.part += 1

    # --- checkpoints ----------------------------------------------------------------------
    def _checkpoint(self, wall: float) -> None:
        assert self.out_dir is not None
        self._close_part()
        meta = {"hash": self.hash, "part": self.part, "stats": self.stats.state(),
                "wstats": self.wstats.state(), "e0": self.e0,
                "emax": self.energy_err_max, "eref": self.energy_ref, "wall": wall}
        tmp = self.out_dir / ".checkpoint.tmp.npz"
        np.savez(tmp, meta=np.array(json.dumps(meta)), R=self.model.work.R,
                 seg=self.model.seg, jp=self.model.jp, topp=self.model.topp,
                 **self.state.arrays())
        os.replace(tmp, self.out_dir / "checkpoint.npz")

    def _restore(self) -> bool:
        assert self.out_dir is not None
        ck = self.out_dir / "checkpoint.npz"
        if not ck.is_file():
            return False
        with np.load(ck) as z:
            meta = json.loads(str(z["meta"]))
            if meta["hash"] != self.hash:
                raise InputError("--resume", "the checkpoint in the run directory belongs to a "
                                 "different configuration", "the same case file as the run")
            for k in ("x", "v", "q", "w", "Fw", "Mw", "Mb", "sc", "hint", "cst"):
                getattr(self.state, k)[...] = z[k]
            self.model.work.R[...] = z["R"]
            self.model.seg[...] = z["seg"]
            self.model.jp[...] = z["jp"]
            self.model.topp[...] = z["topp"]
        self.part = int(meta["part"])
        self.stats.load(meta["stats"])
        self.wstats.load(meta["wstats"])
        self.e0 = float(meta["e0"])
        self.energy_err_max = float(meta["emax"])
        self.energy_ref = float(meta["eref"])
        self.wall_before = float(meta["wall"])
        # drop the parts written after the checkpoint
        for p in self._parts_dir().glob("*.parquet*"):
            idx = int(p.name.split(".")[1])
            if idx >= self.part or p.name.endswith(".open"):
                p.unlink()
        return True

    # --- main loop --------------------------------------------------------------------------
    def run(self, progress: bool, resume: bool) -> SimulationResult:
        od = self.out_dir
        resumed = False
        if od is not None:
            od.mkdir(parents=True, exist_ok=True)
            if resume:
                self._parts_dir().mkdir(exist_ok=True)
                resumed = self._restore()
            if not resumed:
                shutil.rmtree(self._parts_dir(), ignore_errors=True)
                self._parts_dir().mkdir()
                for k in (*FILES, "summary", "joints"):
                    for p in od.glob(f"{k}.*"):
                        p.unlink()
                (od / "checkpoint.npz").unlink(missing_ok=True)
            _atomic_write_text(od / "case.yaml", yaml.safe_dump(
                self.config.model_dump(mode="json"), sort_keys=False))
            self._write_joints()
        m, s = self.model, self.state
        wk = m.work
        params = m.params
        rows = [self.chunk // e + 2 for e in self.every]
        rec0 = new_records(self.sel, tuple(self.every), tuple(rows), m.n)
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
                bl = rec.buf_l[: rec.counts[0]]
                bc = rec.buf_c[: rec.counts[1]]
                bk = rec.buf_k[: rec.counts[2]]
                if rec_on and self.start_step > step:
                    t0 = self.start_step * m.dt - 0.5 * m.dt
                    bl, bc, bk = bl[bl[:, 0] >= t0], bc[bc[:, 0] >= t0], bk[bk[:, 0] >= t0]
                self._account(bc)
                self._write(self._tables(bl, bc, bk))
                if st != ST_OK:
                    try:
                        raise_for_status(st, rec.info, m)
                    except SimulationError as exc:
                        error = exc
                    status = "failed"
                    break
                new_step = int(s.sc[L.C_STEP])
                if od is not None and self.ck_steps and new_step % self.ck_steps == 0 \
                        and new_step < self.n_steps_total:
                    self._checkpoint(self.wall_before + time.perf_counter() - t_wall0)
                if bar is not None:
                    bar.update(new_step * m.dt, self.wall_before + time.perf_counter() - t_wall0)
        except KeyboardInterrupt:
            status = "incomplete"
            raise
        finally:
            if bar is not None:
                bar.close()
            wall = self.wall_before + time.perf_counter() - t_wall0
            result = self._finish(status, wall)
            if error is not None:
                raise error
        return result

    def _account(self, bc: np.ndarray) -> None:
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

    def _write_joints(self) -> None:
        assert self.out_dir is not None
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
        _atomic_write_table(self.out_dir / "joints.parquet", [tab])

    def _finish(self, status: str, wall: float) -> SimulationResult:
        m = self.model
        sim_t = float(self.state.sc[L.C_STEP]) * m.dt
        summary: dict[str, Any] = {
            "status": status,
            "config_hash": self.hash,
            "versions": _versions(),
            "wall_time_s": wall,
            "duration_s": sim_t,
            "duration_requested_s": self.config.operation.duration_s,
            "real_time_factor": sim_t / wall if wall > 0 else None,
            "dt_s": m.dt,
            "n_steps": int(self.state.sc[L.C_STEP]),
            "n_segments": m.n0,
            "n_joints_recorded": int(self.sel.size),
            "hook_load_setpoint_N": m.hook_load_N,
            "wob_initial_N": m.wob0_N,
            "neutral_point_s_from_bit_m": m.neutral_point_s_from_bit_m,
            "top_segment_length_m": m.top_length_m,
            "figures": self.stats.as_dict(self.stats.n),
            "energy_balance_error_J": self.energy_err_max,
            "energy_balance_error_rel": self.energy_err_max / self.energy_ref,
            "work_in_J": float(self.state.sc[L.C_WIN]),
            "dissipated_J": float(self.state.sc[L.C_DISS]),
            "n_segments_initial": m.n0,
            "n_segments_final": self.state.n_active,
            "segments_added": int(self.state.sc[L.C_NSPLIT]),
            "segments_merged": int(self.state.sc[L.C_NMERGE]),
            "bit_md_final_m": float(self.state.sc[L.C_MDROCK]),
            "trip_out_stopped_at_minimum": bool(self.state.sc[L.C_GUARD] == 1.0),
        }
        ev = events_summary(m, self.state, self.wstats)
        summary["events"] = ev
        for k in EVENT_KEYS:
            summary[k] = ev[k]
        res = SimulationResult(status=status, summary=summary, out_dir=self.out_dir, model=m,
                               state=self.state, joints=self.sel)
        if self.out_dir is None:
            loads = self.mem["loads"]
            if loads:
                tab = pa.concat_tables(loads)
                nt = tab.num_rows // max(self.sel.size, 1)
                res.times_s = tab.column("time_s").to_numpy()[:: self.sel.size].copy()
                res.loads = np.stack([tab.column(c).to_numpy() for c in LOAD_COLUMNS],
                                     axis=1).reshape(nt, self.sel.size, 6)
            if self.mem["channels"]:
                tab = pa.concat_tables(self.mem["channels"])
                res.channels = {c: tab.column(c).to_numpy() for c in tab.column_names}
            if self.mem["kinematics"]:
                res.kinematics = pa.concat_tables(self.mem["kinematics"])
            return res
        self._close_part()
        for k in FILES:
            parts = sorted(self._parts_dir().glob(f"{k}.*.parquet"))
            _atomic_write_table(self.out_dir / f"{k}.parquet", parts)
        if status == "complete":
            (self.out_dir / "checkpoint.npz").unlink(missing_ok=True)
            shutil.rmtree(self._parts_dir(), ignore_errors=True)
        _atomic_write_text(self.out_dir / "summary.json", json.dumps(summary, indent=2) + "\n")
        return res


#: Event figures copied to the top level of summary.json (read by the sweep's dataset).
EVENT_KEYS = ("stick_slip_severity", "whirl_class", "bit_bounce_count", "max_contact_force_N",
              "rms_surface_torque_Nm", "peak_surface_torque_Nm")


def classify_whirl(orbit_rad: float, orbit_abs_rad: float, spin_rad: float) -> str:
    """Whirl class of one segment from its orbit and spin angles over the window.

    ``none``: the centre orbits less than one turn in total (|orbit| and the
    summed |d orbit| both < 2 pi); ``chaotic``: the orbit reverses so much that
    the net angle is less than half the summed |d angle|; otherwise ``forward``
    when the orbit turns the same way as the spin, ``backward`` when opposite.
    """
    if orbit_abs_rad < 2.0 * math.pi:
        return "none"
    if abs(orbit_rad) < 0.5 * orbit_abs_rad:
        return "chaotic"
    if spin_rad == 0.0:
        return "chaotic"
    return "forward" if orbit_rad * spin_rad > 0.0 else "backward"


def events_summary(m: Model, s: State, wstats: _Stats) -> dict[str, Any]:
    """Events of a run for summary.json (see the module docstring)."""
    n = s.n_active
    cst = s.cst[:n]
    h = m.seg[:n, L.S_H]
    s_mid = np.cumsum(np.r_[0.0, 2.0 * h[:-1]]) + h
    per_seg = [classify_whirl(float(c[L.CS_ORB]), float(c[L.CS_ORBABS]), float(c[L.CS_SPIN]))
               for c in cst]
    whirling = [c for c in per_seg if c != "none"]
    if whirling:
        vals, counts = np.unique(whirling, return_counts=True)
        dominant = str(vals[int(np.argmax(counts))])
    else:
        dominant = "none"
    onset = [{"segment": i, "time_s": float(c[L.CS_ONT]), "bit_md_m": float(c[L.CS_ONMD]),
              "md_m": float(c[L.CS_ONMD] - s_mid[i])}
             for i, c in enumerate(cst) if c[L.CS_ONT] >= 0.0]
    ws = wstats.as_dict(wstats.n)
    sev = None
    rms = None
    peak = None
    if "bit_rpm" in ws:
        b = ws["bit_rpm"]
        sev = (b["max"] - b["min"]) / b["mean"] if abs(b["mean"]) > 1e-9 else None
        t = ws["surface_torque_Nm"]
        rms = math.sqrt(max(ws["surface_torque_Nm_sq"]["mean"], 0.0))
        peak = max(abs(t["max"]), abs(t["min"]))
    orbit_rate = [float(c[L.CS_ORB]) for c in cst]
    return {
        "window_start_s": float(m.bp[L.B_TWIN]),
        "stick_slip_severity": sev,
        "whirl_class": dominant,
        "whirl_per_segment": per_seg,
        "orbit_angle_rad": orbit_rate,
        "spin_angle_rad": [float(c[L.CS_SPIN]) for c in cst],
        "bit_bounce_count": int(s.sc[L.C_BOUNCE]),
        "max_contact_force_N": float(cst[:, L.CS_FMAX].max()) if n else 0.0,
        "max_contact_force_per_segment_N": [float(c[L.CS_FMAX]) for c in cst],
        "contact_time_s_per_segment": [float(c[L.CS_TCON]) for c in cst],
        "rms_surface_torque_Nm": rms,
        "peak_surface_torque_Nm": peak,
        "contact_onset": onset,
        "segments_in_contact_ever": len(onset),
    }


def _atomic_write_table(path: Path, parts: list[Any]) -> None:
    """Write tables or Parquet part files into one Parquet file, atomically."""
    tmp = path.with_name(f".{path.name}.tmp")
    writer: pq.ParquetWriter | None = None
    try:
        for part in parts:
            if isinstance(part, Path):
                pf = pq.ParquetFile(part)
                for g in range(pf.num_row_groups):
                    tab = pf.read_row_group(g)
                    if writer is None:
                        writer = pq.ParquetWriter(tmp, tab.schema)
                    writer.write_table(tab)
            else:
                if writer is None:
                    writer = pq.ParquetWriter(tmp, part.schema)
                writer.write_table(part)
    finally:
        if writer is not None:
            writer.close()
    if writer is None:
        return
    os.replace(tmp, path)


def _divergence_error(st: int, info: np.ndarray, m: Model) -> SimulationError:
    t = info[0] * m.dt
    i = int(info[1])
    where = f"segment {i} ({m.segments.s_from_bit_m[min(max(i, 0), m.n - 1)]:.1f} m from the bit)" \
        if i >= 0 else "an unknown segment"
    if st == L.ST_NONFINITE:
        why = "non-finite state"
    elif st == L.ST_FORCES:
        why = f"the force evaluation failed (code {int(info[2])}: unknown friction or bit model)"
    else:
        why = f"kinetic energy {info[2]:.3g} J above the blow-up limit {m.bp[L.B_ESCALE]:.3g} J"
    return SimulationError(
        f"simulation diverged at t = {t:.6g} s in {where}: {why}; likely cause: a step too large "
        f"for the stiffest element (dt = {m.dt:.3g} s; lower solver.safety_factor or solver.dt_s) "
        "or an unphysical input (stiffness, contact penalty, speed)")


class _Progress:
    """rich progress bar: simulated time, real-time factor, ETA."""

    def __init__(self, total_s: float) -> None:
        from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

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
        Run directory; without it the histories are returned in memory.
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
        Inconsistent inputs (string longer than the hole, bad joint index...).
    """
    runner = Runner(config, Path(out_dir) if out_dir is not None else None, path)
    return runner.run(progress=progress, resume=resume)
