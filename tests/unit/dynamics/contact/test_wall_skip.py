"""The wall loop skips the force kernel for points off the wall: property tests that the skip
drops nothing (docs/performance.md#where-the-time-of-a-step-goes).

``wall_contact`` locates every contact point (:func:`find_contact`) and calls
:func:`located_wall_force` only where the penetration is positive; ``wall_force`` (search +
force kernel, the form the loop used before) is the reference. Exact equality is asserted:
the skip is a pure speed-up, the same floating-point operations in the same order.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.contact.wall import (
    build_cylinder_chain,
    find_contact,
    located_wall_force,
    wall_force,
)
from drillfatigue.config.friction import FrictionConfig
from drillfatigue.dynamics.contact.friction import I_AX_RATIO, TANH_EXP, pack_friction_params
from drillfatigue.dynamics.core.layout import WALL_INFO_SIZE, WI_DELTA

R_HOLE = 0.108
N_CYL = 12
L_CYL = 1.5


def chain(dogleg_deg: float):
    """A centre line turning by ``dogleg_deg`` per cylinder in the x-z plane."""
    pts = [np.zeros(3)]
    ang = 0.0
    for _ in range(N_CYL):
        pts.append(pts[-1] + L_CYL * np.array([math.sin(ang), 0.0, math.cos(ang)]))
        ang += math.radians(dogleg_deg)
    return build_cylinder_chain(np.array(pts), R_HOLE)


def friction_params() -> np.ndarray:
    # mu_axial / mu_dynamic = 1.2; tanh_exp with v_t = 0.01, v_s = 0.2 m/s
    _, fp = pack_friction_params(FrictionConfig(model="tanh_exp", mu_static=0.35,
                                                mu_dynamic=0.25, mu_axial=0.3,
                                                v_t_m_per_s=0.01, v_s_m_per_s=0.2))
    assert fp[I_AX_RATIO] == pytest.approx(1.2)
    return fp


finite = st.floats(-3.0, 3.0, allow_nan=False)
vec3 = st.tuples(finite, finite, finite)


@settings(max_examples=300, deadline=None)
@given(dogleg=st.floats(0.0, 8.0), cyl=st.integers(0, N_CYL - 1), s=st.floats(0.0, 1.0),
       radial=st.floats(0.0, 0.15), phi=st.floats(0.0, 2.0 * math.pi),
       r_contact=st.floats(0.05, 0.09), hint=st.integers(-3, N_CYL + 3), vc=vec3, omega=vec3)
def test_skip_drops_nothing_and_the_force_is_the_same(dogleg, cyl, s, radial, phi, r_contact,
                                                      hint, vc, omega):
    p0, axis, length, radius = chain(dogleg)
    # a point at a chosen distance from cylinder cyl's axis, in any direction
    a = axis[cyl]
    u = np.cross(a, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(a, u)
    X = p0[cyl] + s * length[cyl] * a + radial * (math.cos(phi) * u + math.sin(phi) * w)
    xc = X - 2.0 * a
    t_axis = a.copy()
    vc = np.array(vc)
    omega = np.array(omega)
    fp = friction_params()
    fo = np.zeros(3)
    dt = 2e-4

    ref_info = np.full(WALL_INFO_SIZE, np.nan)
    ref_f = np.full(3, np.nan)
    ref_m = np.full(3, np.nan)
    body = (xc, vc, omega, t_axis)
    law = (5e7, 5e4, TANH_EXP, fp, dt)
    st_ref = wall_force(X, r_contact, body, (p0, axis, length, radius), hint, law, fo,
                        (ref_info, ref_f, ref_m))

    info = np.full(WALL_INFO_SIZE, np.nan)
    ic = find_contact(X, r_contact, p0, axis, length, radius, hint, info)
    np.testing.assert_array_equal(info[:6], ref_info[:6])
    if info[WI_DELTA] <= 0.0:
        # skipped: the reference kernel gives exactly no force there
        assert np.all(ref_f == 0.0) and np.all(ref_m == 0.0)
    else:
        f = np.full(3, np.nan)
        m = np.full(3, np.nan)
        st_new = located_wall_force(X, r_contact, ic, body, law, fo, (info, f, m))
        assert st_new == st_ref
        np.testing.assert_array_equal(info, ref_info)
        np.testing.assert_array_equal(f, ref_f)
        np.testing.assert_array_equal(m, ref_m)


@settings(max_examples=200, deadline=None)
@given(cyl=st.integers(1, N_CYL - 2), s=st.floats(0.05, 0.95), depth=st.floats(1e-6, 0.01),
       phi=st.floats(0.0, 2.0 * math.pi), r_contact=st.floats(0.05, 0.09),
       hint=st.integers(0, N_CYL - 1))
def test_a_point_through_the_wall_is_never_skipped(cyl, s, depth, phi, r_contact, hint):
    """In a straight hole a point ``depth`` beyond the clearance penetrates by ``depth``
    (closed form): the loop must see delta > 0 and call the force kernel. Tolerance 1e-12 m:
    a few ulps of the 0.1 m distances involved."""
    p0, axis, length, radius = chain(0.0)
    clearance = R_HOLE - r_contact
    X = p0[cyl] + s * length[cyl] * axis[cyl] + (clearance + depth) * np.array(
        [math.cos(phi), math.sin(phi), 0.0])
    info = np.zeros(WALL_INFO_SIZE)
    find_contact(X, r_contact, p0, axis, length, radius, hint, info)
    assert info[WI_DELTA] > 0.0
    assert abs(info[WI_DELTA] - depth) < 1e-12
