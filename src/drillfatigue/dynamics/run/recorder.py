"""Recorder: the integrator's record buffers turned into tables, kept in memory or as Parquet parts.

:func:`drillfatigue.dynamics.step.integrator.advance` fills three buffers per
chunk (loads of the recorded joints, channels, kinematics; layouts in
:class:`drillfatigue.dynamics.core.bundles.Records`). :class:`Recorder` converts
them into the tables of the run directory (:mod:`drillfatigue.rundir`) and

* without a run folder, keeps them in memory (:meth:`Recorder.in_memory`);
* with one, streams them into part files in its parts folder, one part per
  checkpoint interval (:meth:`Recorder.close_part`), and at the end of the
  run merges the parts into the final files (complete run) or into
  ``<name>.partial.parquet`` (failed run); an interrupted run keeps its parts
  for ``--resume`` and writes nothing under a final name.

Every file is written under a temporary name and renamed, and recorded in
the folder's ownership marker (:class:`drillfatigue.files.OutputFolder`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from drillfatigue import rundir
from drillfatigue.dynamics.core import layout as L
from drillfatigue.files import OutputFolder, atomic_output

_CH_INDEX = (L.H_TSURF, L.H_HOOK, L.H_WOB, L.H_TOB, L.H_TOPRPM, L.H_BITRPM, L.H_BITMD, L.H_ROP)
_KIN_VALUES = rundir.KINEMATICS_COLUMNS[3:]


def write_table(folder: OutputFolder, name: str, parts: list[Any]) -> bool:
    """Write tables or Parquet part files (paths) into ``folder/name`` as one Parquet file,
    atomically; returns False (writing nothing) when there is no data."""
    writer: pq.ParquetWriter | None = None
    target = folder.path / name
    with atomic_output(target) as tmp:
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
            raise _NoData
        folder.file(name)
    return True


class _NoData(Exception):
    """No rows to write (atomic_output then leaves nothing behind)."""


class Recorder:
    """Recorded histories of one run (see the module docstring).

    Parameters
    ----------
    seg_s_from_bit_m : ndarray, shape (n_joint,)
        Distance of every joint from the bit (m), for the ``md_m`` column.
    sel : ndarray of int64
        Joints recorded.
    n_rows : int
        Allocated segment rows (kinematics buffer width).
    folder : OutputFolder or None
        The run folder; None keeps everything in memory.
    """

    def __init__(self, joint_s_from_bit_m: np.ndarray, sel: np.ndarray, n_rows: int,
                 folder: OutputFolder | None) -> None:
        self.joint_s = joint_s_from_bit_m
        self.sel = sel
        self.n_rows = n_rows
        self.folder = folder
        self.part = 0
        self.writers: dict[str, pq.ParquetWriter] = {}
        self.mem: dict[str, list[pa.Table]] = {k: [] for k in rundir.HISTORIES}

    # --- buffers -> tables ------------------------------------------------------------
    def tables(self, bl: np.ndarray, bc: np.ndarray, bk: np.ndarray, seg: np.ndarray,
               md_rock_m: float) -> dict[str, pa.Table]:
        """Tables of one chunk: loads ``bl``, channels ``bc``, kinematics ``bk`` (rows as
        written by the integrator); ``seg`` the segment parameters now, ``md_rock_m`` the
        bit MD when no channel row gives it."""
        out: dict[str, pa.Table] = {}
        nsel = self.sel.size
        if bl.shape[0]:
            t = bl[:, 0]
            ld = bl[:, 1:1 + 6 * nsel].reshape(bl.shape[0], nsel, 6)
            if bc.shape[0]:
                md_bit = np.interp(t, bc[:, 0], bc[:, 1 + L.H_BITMD])
            else:
                md_bit = md_rock_m + 0.0 * t
            cols: dict[str, Any] = {
                "time_s": np.repeat(t, nsel),
                "joint": np.tile(self.sel, t.size).astype(np.int32),
                "md_m": (md_bit[:, None] - self.joint_s[self.sel][None, :]).ravel(),
            }
            for k, name in enumerate(rundir.LOAD_COLUMNS):
                cols[name] = ld[:, :, k].ravel()
            if bl.shape[1] > 1 + 6 * nsel:  # the span-bending correction was recorded
                sp = bl[:, 1 + 6 * nsel:].reshape(bl.shape[0], nsel, 2)
                for k, name in enumerate(rundir.SPAN_COLUMNS):
                    cols[name] = sp[:, :, k].ravel()
            out["loads"] = pa.table(cols)
        if bc.shape[0]:
            cols = {"time_s": bc[:, 0]}
            for name, k in zip(rundir.CHANNEL_COLUMNS, _CH_INDEX, strict=True):
                cols[name] = bc[:, 1 + k]
            cols["kinetic_energy_J"] = bc[:, 1 + L.N_CH]
            cols["potential_energy_J"] = bc[:, 1 + L.H_PE] + bc[:, 1 + L.H_PG]
            cols["work_in_J"] = bc[:, 2 + L.N_CH]
            cols["dissipated_J"] = bc[:, 3 + L.N_CH]
            cols["segments_in_contact"] = bc[:, 1 + L.H_NCON]
            cols["max_contact_force_N"] = bc[:, 1 + L.H_FCMAX]
            cols["n_segments"] = bc[:, 1 + L.H_NSEG]
            for k, name in enumerate(rundir.RIG_CHANNEL_COLUMNS[: bc.shape[1] - 4 - L.N_CH]):
                cols[name] = bc[:, 4 + L.N_CH + k]
            out["channels"] = pa.table(cols)
        if bk.shape[0]:
            n = self.n_rows
            t = bk[:, 0]
            kv = bk[:, 1:].reshape(t.size, n, 8)
            h = seg[:, L.S_H]
            s_mid = np.cumsum(np.r_[0.0, 2.0 * h[:-1]]) + h
            tt = np.repeat(t, n)
            sg = np.tile(np.arange(n, dtype=np.int32), t.size)
            flat = kv.reshape(-1, 8)
            act = np.isfinite(flat[:, 0])
            cols = {"time_s": tt[act], "segment": sg[act], "s_from_bit_m": np.tile(s_mid, t.size)[act]}
            for k, name in enumerate(_KIN_VALUES):
                cols[name] = flat[act, k]
            out["kinematics"] = pa.table(cols)
            con = act & (np.nan_to_num(flat[:, 6]) > 0.0)
            out["contacts"] = pa.table({"time_s": tt[con], "segment": sg[con],
                                        "normal_N": flat[con, 6],
                                        "dist_from_centre_m": flat[con, 7]})
        return out

    # --- keeping them -----------------------------------------------------------------
    def write(self, tables: dict[str, pa.Table]) -> None:
        """Append the tables: to memory, or to the open part files."""
        if self.folder is None:
            for k, tab in tables.items():
                self.mem[k].append(tab)
            return
        for k, tab in tables.items():
            w = self.writers.get(k)
            if w is None:
                w = pq.ParquetWriter(self.folder.file(rundir.part_name(k, self.part, True)),
                                     tab.schema)
                self.writers[k] = w
            w.write_table(tab)

    def start(self) -> None:
        """Fresh run: an empty parts folder."""
        assert self.folder is not None
        (self.folder.path / rundir.PARTS).mkdir(exist_ok=True)
        self.part = 0

    def close_part(self) -> None:
        """Close the open part files (they become final parts)."""
        if self.folder is None:
            return
        for k in list(self.writers):
            self.writers.pop(k).close()
            name = rundir.part_name(k, self.part, True)
            final = rundir.part_name(k, self.part)
            self.folder.file(final)
            os.replace(self.folder.path / name, self.folder.path / final)
            self.folder.remove([name])
        self.part += 1

    def resume_at(self, part: int) -> None:
        """Continue with part ``part``: drop the parts written after the checkpoint."""
        assert self.folder is not None
        (self.folder.path / rundir.PARTS).mkdir(exist_ok=True)
        self.part = part
        self.folder.remove([name for name in sorted(self.folder.owned)
                            if name.startswith(rundir.PARTS + "/")
                            and (name.endswith(".open") or int(name.split(".")[-2]) >= part)])

    def part_files(self, stem: str) -> list[Path]:
        assert self.folder is not None
        names = sorted(n for n in self.folder.owned
                       if n.startswith(f"{rundir.PARTS}/{stem}.") and n.endswith(".parquet"))
        return [self.folder.path / n for n in names]

    def finish(self, status: str) -> list[str]:
        """End of run: ``complete`` merges the parts into the final files and removes them;
        ``failed`` merges them into ``<name>.partial.parquet``; ``incomplete`` keeps them
        (for ``--resume``). Returns the history files written."""
        if self.folder is None or status == "incomplete":
            self.close_part()
            return []
        self.close_part()
        written = []
        for k in rundir.HISTORIES:
            name = rundir.history_name(k) if status == "complete" else rundir.partial_name(k)
            try:
                write_table(self.folder, name, list(self.part_files(k)))
            except _NoData:
                continue
            written.append(name)
        if status == "complete":
            self.folder.remove([n for n in sorted(self.folder.owned)
                                if n.startswith(rundir.PARTS + "/")])
            try:
                (self.folder.path / rundir.PARTS).rmdir()
            except OSError:  # a foreign file in the parts folder: leave it
                pass
        return written

    def in_memory(self) -> dict[str, Any]:
        """The histories kept in memory: ``times_s``, ``loads`` (n_time, n_joint, 6),
        ``channels`` (dict of columns), ``kinematics`` (a pyarrow table or None)."""
        out: dict[str, Any] = {"times_s": None, "loads": None, "channels": {}, "kinematics": None}
        nsel = self.sel.size
        if self.mem["loads"]:
            tab = pa.concat_tables(self.mem["loads"])
            nt = tab.num_rows // max(nsel, 1)
            out["times_s"] = tab.column("time_s").to_numpy()[::nsel].copy()
            out["loads"] = np.stack([tab.column(c).to_numpy() for c in rundir.LOAD_COLUMNS],
                                    axis=1).reshape(nt, nsel, 6)
            if rundir.SPAN_COLUMNS[0] in tab.column_names:
                out["span_bending"] = np.stack(
                    [tab.column(c).to_numpy() for c in rundir.SPAN_COLUMNS],
                    axis=1).reshape(nt, nsel, 2)
        if self.mem["channels"]:
            tab = pa.concat_tables(self.mem["channels"])
            out["channels"] = {c: tab.column(c).to_numpy() for c in tab.column_names}
        if self.mem["kinematics"]:
            out["kinematics"] = pa.concat_tables(self.mem["kinematics"])
        return out
