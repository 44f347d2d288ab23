"""Static hook load in a vertical hole = buoyed weight - WOB; neutral point (docs/validation.md).

Buoyed weight W_b = (1 - rho_mud / rho_steel) g sum(rho A L) (Archimedes, open
pipe, mud inside and out); the neutral point is where the effective tension
changes sign, at the depth where the buoyed weight below it equals the WOB.
The reference numbers are computed here from the case data, not from the model.
The run starts from a perturbed state and settles under joint and mud damping.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path

G = 9.80665
RHO_S, RHO_MUD = 7850.0, 1200.0
DC = (0.17145, 0.0714, 60.0, 6)      # od, id, length, segments
DP = (0.127, 0.1086, 240.0, 24)


def _case(top_axial: str, hook_load: float = 0.0):
    comps = [{"type": t, "od_m": od, "id_m": i, "length_m": ln, "n_segments": ns}
             for t, (od, i, ln, ns) in (("collar", DC), ("drill_pipe", DP))]
    return case_from_dict({
        "string": {"components": comps},
        "operation": {"bit_md_m": 300.0, "top_axial": top_axial, "hook_load_N": hook_load,
                      "rpm": 0.0, "rpm_ramp_s": 0.0, "mud_density_kg_per_m3": RHO_MUD,
                      "mud_damping_axial_N_s_per_m2": 200.0},
        "solver": {"joint_damping_ratio": 0.2},
    })


def _weights() -> tuple[float, float]:
    """Buoyed weight per metre of collars and of drill pipe (N/m)."""
    bf = 1.0 - RHO_MUD / RHO_S
    return tuple(bf * G * RHO_S * math.pi / 4 * (od ** 2 - i ** 2) for od, i, _, _ in (DC, DP))


def _settle(cfg):
    model, state = build_model(cfg, straight_path(500.0))
    rng = np.random.default_rng(3)
    state.v[:, 2] += rng.normal(0.0, 0.05, model.n)  # perturb: the model must find the statics
    n_steps = int(2.0 / model.dt)
    out = advance_model(model, state, n_steps, every=20)
    return model, out


def test_hook_load_equals_buoyed_weight_minus_wob() -> None:
    w_dc, w_dp = _weights()
    w_total = w_dc * DC[2] + w_dp * DP[2]
    hook = 0.8 * w_total
    model, out = _settle(_case("hook_load", hook))
    ch = out["channels"]
    tail = ch[-20:]
    from drillfatigue.dynamics.core import layout as L
    wob = tail[:, 1 + L.H_WOB].mean()
    # 0.5 % (the bound); damping settles the perturbation to << 0.1 %
    assert abs(wob - (w_total - hook)) <= 0.005 * (w_total - hook)
    assert abs(tail[:, 1 + L.H_HOOK].mean() - hook) <= 1e-9 * hook


def test_neutral_point_at_top_of_collars() -> None:
    w_dc, w_dp = _weights()
    model, out = _settle(_case("neutral_point"))
    axial = out["loads"][-10:, :, 0].mean(axis=0)
    s = model.segments.joint_s_from_bit_m
    k = int(np.nonzero(np.diff(np.sign(axial)))[0][0])
    s_np = s[k] - axial[k] * (s[k + 1] - s[k]) / (axial[k + 1] - axial[k])
    # the neutral point (tension = 0) sits at the top of the collars (60 m),
    # within 1 % of a segment length of interpolation between joints
    assert abs(s_np - DC[2]) < 0.1
    # and the hook load is the buoyed weight of the pipe above it
    assert math.isclose(model.hook_load_N, w_dp * DP[2], rel_tol=1e-9)
