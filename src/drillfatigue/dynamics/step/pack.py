"""The step of a case: the stable velocity-Verlet step, the energy scale of the blow-up check."""

from __future__ import annotations


import math

import numpy as np

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.contact.friction import registry as friction
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.top.growth import update_top
from drillfatigue.errors import InputError


def stable_step(seg: np.ndarray, jp: np.ndarray, bp: np.ndarray,
                cpar: np.ndarray | None = None, cp_n: np.ndarray | None = None) -> float:
    """Largest stable velocity-Verlet step (s) before the safety factor.

    Gershgorin bound on the eigenvalues of M^-1/2 K M^-1/2 of the linearised
    chain: per segment and per kind of DOF, the sum over its joints of
    |K_ab| / sqrt(m_a m_b), including the shear lever arms h and the boundary
    springs; omega_max^2 <= the largest row sum. dt = 2 / omega_max times
    (sqrt(1 + zeta^2) - zeta) for the largest damping ratio.

    With wall contact (``cpar[P_ON] != 0``) every contact point adds its
    penalty spring k_c (translation, and tilt through the lever arm h), and the
    a stiction law (Karnopp) adds the limit dt < 2 m_eff v_min / (mu_s N) (a slip
    overshoot in one step must land inside the stick band; m_eff = m / 3 for
    rolling/spinning), with N estimated as twice the segment's buoyed weight;
    the smaller step is taken. The smooth friction laws need no such limit:
    the force kernel caps their tangential force so one step cannot reverse
    the slip (:func:`drillfatigue.dynamics.contact.wall.wall_contact`). ``cp_n``
    (n,): contact points of each segment when they come from the string
    (``cpar[P_CPTAB]``), else every segment has ``cpar[P_NPTS]``.

    Not counted: the bit law's own damping of the bit segment's spin, ``c =
    dTOB/dOmega`` (it depends on the WOB of the moment; 2.4e4 N m s/rad just above
    the Yigit-Christoforou speed threshold at 100 kN), whose explicit limit ``2 I_a /
    c`` can lie below this bound (2.8e-4 s against 3.65e-4 s on the paper string);
    ``solver.implicit_bit_torque`` takes it implicitly
    (:func:`drillfatigue.dynamics.top.boundaries.implicit_bit_damping`).
    """
    n = seg.shape[0]
    m = seg[:, L.S_M]
    it = seg[:, L.S_IT]
    ia = seg[:, L.S_IA]
    h = seg[:, L.S_H]
    rows = np.zeros((n, 4))  # lateral, axial, bending, torsion

    def add(a: int, b: int, row: int) -> None:
        ka, ks, kb, kt = jp[row, L.J_KA], jp[row, L.J_KS], jp[row, L.J_KB], jp[row, L.J_KT]
        for p, o in ((a, b), (b, a)):
            if o < 0:
                rows[p, 0] += ks / m[p] + ks * h[p] / math.sqrt(m[p] * it[p])
                rows[p, 1] += ka / m[p]
                rows[p, 2] += (kb + ks * h[p] ** 2) / it[p] + ks * h[p] / math.sqrt(it[p] * m[p])
                rows[p, 3] += kt / ia[p]
                continue
            if p < 0:
                continue
            rows[p, 0] += (ks / m[p] + ks / math.sqrt(m[p] * m[o])
                           + ks * h[p] / math.sqrt(m[p] * it[p]) + ks * h[o] / math.sqrt(m[p] * it[o]))
            rows[p, 1] += ka / m[p] + ka / math.sqrt(m[p] * m[o])
            rows[p, 2] += ((kb + ks * h[p] ** 2) / it[p] + (kb + ks * h[p] * h[o]) / math.sqrt(it[p] * it[o])
                           + ks * h[p] / math.sqrt(it[p] * m[p]) + ks * h[p] / math.sqrt(it[p] * m[o]))
            rows[p, 3] += kt / ia[p] + kt / math.sqrt(ia[p] * ia[o])

    for j in range(n - 1):
        add(j, j + 1, j)
    add(n - 1, -1, n - 1)
    if bp[L.B_BITON] == 1.0:
        kbit = bp[L.B_KBIT]
        rows[0, 0] += kbit / m[0] + kbit * h[0] / math.sqrt(m[0] * it[0])
        rows[0, 1] += kbit / m[0]
        rows[0, 2] += kbit * h[0] ** 2 / it[0] + kbit * h[0] / math.sqrt(m[0] * it[0])
    dt_f = math.inf
    zc = 0.0
    if cpar is not None and cpar[L.P_ON] != 0.0:
        fr = friction
        kc = cpar[L.P_KC]
        npts = cpar[L.P_NPTS]
        if cp_n is not None and cpar[L.P_CPTAB] != 0.0:
            npts = np.maximum(cp_n[:n], npts)
        rows[:, 0] += npts * kc / m + 2.0 * kc * h / np.sqrt(m * it)
        rows[:, 2] += 2.0 * kc * h ** 2 / it + 2.0 * kc * h / np.sqrt(m * it)
        fp = cpar[L.P_FP:L.P_FP + fr.N_PARAMS]
        law = int(cpar[L.P_FMODEL])
        vmin = fr.slip_scale_m_per_s(law, fp)
        mu = max(fp[fr.I_MU_S], fp[fr.I_MU_D] * max(fp[fr.I_AX_RATIO], 1.0))
        w_seg = np.abs(seg[:, L.S_W]) + 1e-12
        if mu > 0.0 and fr.has_stiction(law):
            dt_f = float((2.0 * (m / 3.0) * vmin / (mu * 2.0 * w_seg)).min())
        cc = seg[:, L.S_CC]
        zc = float((cc / (2.0 * np.sqrt(kc * m / npts))).max())
    omega_max = math.sqrt(float(rows.max()))
    zeta = max(bp[L.B_ZB], bp[L.B_ZJ], zc)
    return min(2.0 / omega_max * (math.sqrt(1.0 + zeta * zeta) - zeta), dt_f)


def choose_step(config: CaseConfig, seg: np.ndarray, jp: np.ndarray, bp: np.ndarray,
                topp: np.ndarray, cpar: np.ndarray, cp_n: np.ndarray | None = None) -> float:
    """The step (s): ``solver.dt_s`` if given (checked against the stable step), else the
    largest step below safety x stable that divides the loads recording interval."""
    op = config.operation
    sv = config.solver
    n = seg.shape[0]
    dt_stable = stable_step(seg, jp, bp, cpar, cp_n)
    if not op.bit_on_bottom and op.trip_speed_m_per_s < 0.0 and n >= 2:
        # tripping out shortens the top segment to B_LMIN before it merges: a
        # lighter body on stiffer springs; take the step for that shortest top too
        seg_s, jp_s = seg.copy(), jp.copy()
        update_top(0.5 * bp[L.B_LMIN], n, seg_s, jp_s, topp, bp)
        dt_stable = min(dt_stable, stable_step(seg_s, jp_s, bp, cpar, cp_n))
    if sv.dt_s is not None:
        dt = sv.dt_s
        if dt > dt_stable:
            raise InputError("solver.dt_s", f"{dt} s exceeds the stable step {dt_stable:.3g} s",
                             f"<= {dt_stable:.3g} s")
        return dt
    t_rec = 1.0 / config.recording.loads_rate_hz
    return t_rec / math.ceil(t_rec / (sv.safety_factor * dt_stable) - 1e-9)


def energy_scale(config: CaseConfig, seg: np.ndarray, bp: np.ndarray, tab_w: np.ndarray,
                 total_ax: float, length_m: float) -> float:
    """Blow-up limit of the kinetic energy (J): ``solver.energy_blowup_factor`` x (weight x
    length + spin energy at the top speed + translation at the ROP + 1 J)."""
    op = config.operation
    omega_max = float(np.abs(tab_w).max())
    if op.top_mode == "torque":
        # steady spin under the applied torque against the mud: omega = T / sum(c_rot)
        c_rot = float(seg[:, L.S_CRA].sum()) + 1e-9
        omega_max = max(omega_max, abs(op.top_torque_Nm) / c_rot)
    e_scale = (abs(total_ax) * length_m + 0.5 * float(seg[:, L.S_IA].sum()) * omega_max ** 2
               + 0.5 * float(seg[:, L.S_M].sum()) * (bp[L.B_ROP] ** 2) + 1.0)
    return config.solver.energy_blowup_factor * e_scale

