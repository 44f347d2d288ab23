"""The run directory of one simulation: file names, columns and their units, defined once.

Written by the simulator (:mod:`drillfatigue.dynamics.run.simulation`), read by the
fatigue chain, the sweep, the studies and the tests. All quantities SI; each
column name carries its unit.

``loads.parquet``
    One row per (time, joint): :data:`LOADS_COLUMNS`, then
    :data:`SPAN_COLUMNS` when the span correction is recorded. Joint frame, z
    along the pipe axis pointing downhole; axial > 0 in tension; the loads
    the upper part exerts on the lower part.
``joints.parquet``
    One row per recorded joint: :data:`JOINTS_COLUMNS`.
``channels.parquet``
    :data:`CHANNELS_COLUMNS`: surface and bit channels and the energy terms.
``kinematics.parquet``
    :data:`KINEMATICS_COLUMNS` (active segments only).
``contacts.parquet``
    :data:`CONTACTS_COLUMNS`: one row per (time, segment in wall contact).
``case.yaml``, ``summary.json`` (written last; ``status`` is ``complete``,
``incomplete`` or ``failed``).

Until a run completes its histories exist only as parts in :data:`PARTS`
(``<name>.<part>.parquet``, the open one ``... .parquet.open``); a failed run
merges them into ``<name>.partial.parquet`` (:func:`partial_name`), a name no
reader takes for a result. ``checkpoint.npz`` lets ``--resume`` continue.
The folder carries the ownership marker of :class:`drillfatigue.files.OutputFolder`
of kind :data:`KIND`.
"""

from __future__ import annotations

import numpy as np

KIND = "run"

LOADS = "loads.parquet"
JOINTS = "joints.parquet"
CHANNELS = "channels.parquet"
KINEMATICS = "kinematics.parquet"
CONTACTS = "contacts.parquet"
SUMMARY = "summary.json"
CASE = "case.yaml"
CHECKPOINT = "checkpoint.npz"
PARTS = ".parts"

#: histories streamed as parts while the run goes on, by stem
HISTORIES = ("loads", "channels", "kinematics", "contacts")

#: the six joint loads, in the order of every load array (n_time, n_joint, 6)
LOAD_COLUMNS = ("axial_N", "shear_x_N", "shear_y_N", "bending_x_Nm", "bending_y_Nm", "torque_Nm")
LOADS_COLUMNS = ("time_s", "joint", "md_m") + LOAD_COLUMNS
#: span-bending correction (joint frame, N m), after LOADS_COLUMNS when ``contact.span_bending``
#: is on: the bending between the wall supports, apart from the joint moment; the
#: fatigue chain adds it to ``bending_x_Nm`` / ``bending_y_Nm``
SPAN_COLUMNS = ("span_bending_x_Nm", "span_bending_y_Nm")
JOINTS_COLUMNS = ("joint", "component", "component_type", "s_from_bit_m", "body_od_m",
                  "body_id_m", "conn_od_m", "conn_id_m")
#: surface and bit channels recorded with the forces
CHANNEL_COLUMNS = ("surface_torque_Nm", "hook_load_N", "wob_N", "tob_Nm", "top_rpm", "bit_rpm",
                   "bit_md_m", "rop_m_per_s")
CHANNELS_COLUMNS = (("time_s",) + CHANNEL_COLUMNS
                    + ("kinetic_energy_J", "potential_energy_J", "work_in_J", "dissipated_J",
                       "segments_in_contact", "max_contact_force_N", "n_segments"))
#: channels added with the rig boundaries (docs/bending.md; docs/rig.md)
RIG_CHANNEL_COLUMNS = ("block_travel_m", "block_velocity_m_per_s", "string_top_above_rotary_m",
                       "connection_phase")
KINEMATICS_COLUMNS = ("time_s", "segment", "s_from_bit_m", "x_m", "y_m", "z_m", "vx_m_per_s",
                      "vy_m_per_s", "vz_m_per_s", "normal_N", "dist_from_centre_m")
CONTACTS_COLUMNS = ("time_s", "segment", "normal_N", "dist_from_centre_m")


def recorded_span_s(time_s: np.ndarray) -> float:
    """Exposure time a recorded history stands for, s: last minus first sample plus one
    sample step (each sample stands for the step after it); 0 for fewer than two samples.

    Damage rates divide by this, not by the run's ``duration_s``: the recording
    starts at ``recording.start_s`` (after the rpm ramp), so the two differ.
    """
    t = np.unique(np.asarray(time_s, dtype=float))
    if t.size < 2:
        return 0.0
    return float(t[-1] - t[0] + (t[1] - t[0]))


def history_name(stem: str) -> str:
    """Final file name of a history (``loads`` -> ``loads.parquet``)."""
    return f"{stem}.parquet"


#: the files a run writes at the top of its folder (checked for foreign files of
#: these names before anything in the folder changes)
FILES = (CASE, JOINTS, SUMMARY, CHECKPOINT) + tuple(history_name(h) for h in HISTORIES)


def partial_name(stem: str) -> str:
    """File name of the data of a run that failed (``loads`` -> ``loads.partial.parquet``)."""
    return f"{stem}.partial.parquet"


def part_name(stem: str, part: int, open_: bool = False) -> str:
    """Name (relative to the run folder) of part ``part`` of a history; ``open_``: still written."""
    return f"{PARTS}/{stem}.{part:05d}.parquet" + (".open" if open_ else "")
