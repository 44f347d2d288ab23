"""The multi-plane kernel against a per-plane loop."""

from __future__ import annotations

import numpy as np
import pytest

import drillfatigue.fatigue.kernels as K
from drillfatigue.fatigue.critical_plane import (CriterionParams, plane_damage, plane_grid,
                                                  shear_groups)
from drillfatigue.fatigue.rainflow import find_cycles_indexed
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import SCF, Section, surface_coefficients
from drillfatigue.status import OK, STACK_OVERFLOW


def test_multiplane_kernel_equals_per_plane_reversal_search() -> None:
    rng = np.random.default_rng(11)
    n = 1500
    t = np.arange(n) * 1e-3
    L = np.column_stack([
        1e5 + 2e4 * np.sin(2 * np.pi * 7.5 * t), 1e3 * rng.normal(size=n),
        1e3 * rng.normal(size=n), 2e4 * np.sin(2 * np.pi * 2.5 * t) + 300 * rng.normal(size=n),
        2e4 * np.cos(2 * np.pi * 2.5 * t), 1.5e4 + 3e3 * np.sin(2 * np.pi * 0.3 * t)])
    cs, ct, _ = surface_coefficients(Section(0.127, 0.1086), SCF(1, 2, 1.5), 36)
    planes = plane_grid(20.0, True, 2)
    curve, prm = get_curve("B1"), CriterionParams()
    for crit, residue in (("findley", "half"), ("matake", "repeat")):
        dmg, _, _ = plane_damage(L, cs, ct, planes, curve, crit, prm, residue)
        pts = range(0, 36, 5)
        ref = _reference_damage(L, cs, ct, planes, curve, crit, prm, residue, pts)
        for p in pts:
            # exact counting either way: only summation order differs
            np.testing.assert_allclose(dmg[p], ref[p], rtol=1e-10)


def _reference_damage(L, cs, ct, planes, curve, crit, prm, residue, points):
    """Per-plane reversal search + rainflow + Miner, plain numpy (the kernel's spec)."""
    ca, cb, _ = prm.constants(crit)
    sig, tau = cs @ L.T, ct @ L.T
    ref = np.zeros((cs.shape[0], len(planes)))
    for p in points:
        for j in range(len(planes)):
            tj = planes.c[j, 0] * sig[p] + planes.c[j, 1] * tau[p]
            nj = planes.n[j, 0] * sig[p] + planes.n[j, 1] * tau[p]
            i0, i1, cnt = find_cycles_indexed(tj, residue)
            dt = np.abs(tj[i1] - tj[i0])
            snmax = np.maximum(nj[i0], nj[i1])
            if crit == "findley":
                seq = cb * (dt / 2 + ca * snmax)
            elif crit == "matake":
                seq = ca * (dt / 2 + cb * np.maximum(snmax, 0))
            else:  # fatemi_socie, stress form
                seq = dt * (1 + ca * np.maximum(snmax, 0) * cb)
            ref[p, j] = np.sum(cnt / curve.cycles_to_failure(2 * np.maximum(seq, 0)))
    return ref


def _noisy_loads(seed: int, n: int) -> np.ndarray:
    """Loads (n, 6) at 1 kHz: axial and rotating-bending tones plus noisy
    shear and torque (N, N m)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 1e-3
    L = np.column_stack([
        1e5 + 2e4 * np.sin(2 * np.pi * 7.5 * t), 2e3 * rng.normal(size=n),
        2e3 * rng.normal(size=n), 2e4 * np.sin(2 * np.pi * 2.5 * t) + 500 * rng.normal(size=n),
        2e4 * np.cos(2 * np.pi * 2.5 * t), 1.5e4 + 3e3 * rng.normal(size=n)])
    return L


def test_conjugate_groups_batches_and_blocks_equal_per_plane_loop() -> None:
    """The 10-degree grid (conjugate planes share one count), histories longer
    than one block (K.BLOCK = 2048 samples) and than one cycle batch per group (256), and
    three curve paths: integer slopes (vectorised), a non-integer slope (scalar
    S-N) and a cut-off. Tolerance 1e-10 relative: exact counting either way,
    only the summation order differs (batch sums are reassociated)."""
    from drillfatigue.fatigue.sn import user_curve

    L = _noisy_loads(5, 9000)
    cs, ct, _ = surface_coefficients(Section(0.127, 0.1086), SCF(1, 2, 1.5), 36)
    planes = plane_grid(10.0)
    prm = CriterionParams()
    curves = (get_curve("D"), user_curve(3.5, 12.2),
              user_curve(3.0, 12.5, 5.0, 1e7, cutoff_N=1e8))
    cases = (("matake", "half", 0), ("findley", "repeat", 1), ("fatemi_socie", "half", 2),
             ("matake", "repeat", 2))
    for crit, residue, ic in cases:
        dmg, _, _ = plane_damage(L, cs, ct, planes, curves[ic], crit, prm, residue)
        pts = range(0, 36, 7)
        ref = _reference_damage(L, cs, ct, planes, curves[ic], crit, prm, residue, pts)
        assert np.all(ref[list(pts)] > 0)
        for p in pts:
            np.testing.assert_allclose(dmg[p], ref[p], rtol=1e-10)


def test_fine_grid_beyond_the_group_mask_equals_per_plane_loop() -> None:
    """A 1-degree grid has 90 shear groups, more than fit the kernel's group bit
    mask (K.MASK_GROUPS): the reversals are then sorted by walking the
    boundaries. Same reference and tolerance as above (1e-10 relative)."""
    L = _noisy_loads(8, 5000)
    cs, ct, _ = surface_coefficients(Section(0.127, 0.1086), SCF(1, 2, 1.5), 36)
    planes = plane_grid(1.0)
    assert shear_groups(planes.c).c.shape[0] > K.MASK_GROUPS
    curve, prm = get_curve("D"), CriterionParams()
    dmg, _, _ = plane_damage(L, cs, ct, planes, curve, "matake", prm, "half")
    pts = (0, 17)
    ref = _reference_damage(L, cs, ct, planes, curve, "matake", prm, "half", pts)
    for p in pts:
        np.testing.assert_allclose(dmg[p], ref[p], rtol=1e-10)


def test_loads_channels_is_the_exact_transpose() -> None:
    from drillfatigue.fatigue.critical_plane import loads_channels

    L = np.random.default_rng(1).normal(size=(9001, 6))
    for x in (L, np.asfortranarray(L), np.vstack([L, L])[::2]):
        assert np.array_equal(loads_channels(x), x.T)
        assert loads_channels(x).flags.c_contiguous


def test_shear_groups_pair_conjugate_planes() -> None:
    planes = plane_grid(10.0, True, 2)
    g = shear_groups(planes.c)
    n_a = 18
    members = [g.cand[g.ptr[i]:g.ptr[i + 1]] for i in range(len(g.ptr) - 1)]
    # family A: theta and theta + 90 together; family B psi = 0 is parallel to A
    for j in range(9):
        grp = next(m for m in members if j in m)
        assert j + 9 in grp
        assert n_a + j in grp and n_a + j + 9 in grp  # family B, psi = 0
    scale = dict(zip(g.cand.tolist(), g.scale.tolist(), strict=False))
    assert scale[n_a] / scale[0] == pytest.approx(np.cos(np.radians(45.0)), rel=1e-12)
    # every candidate with shear belongs to exactly one group
    assert sorted(g.cand.tolist()) == list(range(len(planes)))


def test_dense_refinement_is_the_best_plane_of_the_fine_grid() -> None:
    """refine_planes with n levels returns the governing plane among all planes
    theta0 + k step/2^n, |k| < 2^n (brute force over the same lattice)."""
    from drillfatigue.fatigue.critical_plane import (Governing, PlaneLaw, loads_channels,
                                                     make_planes, pick_planes, refine_planes)

    rng = np.random.default_rng(2)
    n = 3000
    t = np.arange(n) * 1e-3
    L = np.column_stack([
        1e5 + 3e4 * np.sin(2 * np.pi * 3.0 * t), 1e3 * rng.normal(size=n),
        1e3 * rng.normal(size=n), 1.5e4 * np.sin(2 * np.pi * 2.5 * t),
        1.5e4 * np.cos(2 * np.pi * 2.5 * t), 1.2e4 * np.sin(2 * np.pi * 1.1 * t + 0.4)])
    cs, ct, _ = surface_coefficients(Section(0.127, 0.1086), SCF(1, 1, 1), 36)
    curve, prm = get_curve("B1"), CriterionParams()
    rows = np.array([3, 20])
    theta0 = np.array([40.0, 130.0])
    zero = np.zeros(2)
    LT = loads_channels(L)
    d0, s0, p0 = plane_damage(L, cs[rows], ct[rows], make_planes(theta0, zero, zero), curve,
                              "findley", prm)
    start = Governing(theta0, d0[[0, 1], [0, 1]], s0[[0, 1], [0, 1]], p0[[0, 1], [0, 1]])
    th, d, s, _ = refine_planes(LT, cs[rows], ct[rows], start, zero, zero, 10.0, 3,
                                PlaneLaw(curve, "findley", prm, "half", 1.0))
    for r in range(2):
        lattice = (theta0[r] + np.arange(-7, 8) * 10.0 / 8) % 180.0
        pl = make_planes(lattice, np.zeros(15), np.zeros(15))
        dd, ss, _ = plane_damage(L, cs[rows[r:r + 1]], ct[rows[r:r + 1]], pl, curve, "findley",
                                 prm)
        k = int(pick_planes(dd, ss)[0])
        assert th[r] == pytest.approx(lattice[k], abs=1e-9)
        assert d[r] == pytest.approx(dd[0, k], rel=1e-12)


def test_refinement_beyond_the_dense_levels_never_loses_selection_damage() -> None:
    """Levels after the dense grid halve greedily from its best plane, so the
    selected plane's selection damage can only grow with n_refine (Findley:
    selection = damage)."""
    from drillfatigue.fatigue.critical_plane import PlaneSearch, evaluate_location

    rng = np.random.default_rng(4)
    n = 2500
    t = np.arange(n) * 1e-3
    L = np.column_stack([
        8e4 + 2e4 * np.sin(2 * np.pi * 4.0 * t), 800 * rng.normal(size=n),
        800 * rng.normal(size=n), 1.2e4 * np.sin(2 * np.pi * 2.5 * t),
        1.2e4 * np.cos(2 * np.pi * 2.5 * t), 1e4 * np.sin(2 * np.pi * 0.9 * t)])
    sec = Section(0.127, 0.1086)
    curve, prm = get_curve("B1"), CriterionParams()
    d = [evaluate_location(L, sec, SCF(1, 1, 1), curve, "findley", prm,
                           search=PlaneSearch(n_points=36, n_refine=k, n_refine_points=1),
                           with_uniaxial=False).damage
         for k in (0, 2, 4, 6)]
    assert all(b >= a * (1 - 1e-12) for a, b in zip(d, d[1:], strict=False))


def test_a_residue_beyond_the_first_stack_capacity_is_retried_not_lost(monkeypatch) -> None:
    # a reversal at every sample with growing amplitude closes no cycle: the
    # residue holds all 1500 reversals, over the wrapper's first capacity
    # (1024), so the kernel returns STACK_OVERFLOW and the wrapper retries
    n = 1500
    k = np.arange(n)
    L = np.zeros((n, 6))
    L[:, 0] = 1e5 + 50.0 * (1 + k) * (-1.0) ** k
    L[:, 3] = 20.0 * (1 + k) * (-1.0) ** (k + 1)
    cs, ct, _ = surface_coefficients(Section(0.127, 0.1086), SCF(1, 2, 1.5), 12)
    planes = plane_grid(30.0, False, 2)
    curve, prm = get_curve("B1"), CriterionParams()
    kernel, codes = K.multiplane_damage, []

    def recorded(*args):  # noqa: ANN002, ANN202
        codes.append(kernel(*args))
        return codes[-1]

    monkeypatch.setattr(K, "multiplane_damage", recorded)
    dmg, _, _ = plane_damage(L, cs, ct, planes, curve, "findley", prm, "half")
    assert codes == [STACK_OVERFLOW, OK]
    pts = (0, 3, 7)
    ref = _reference_damage(L, cs, ct, planes, curve, "findley", prm, "half", pts)
    top = ref[list(pts)].max()
    assert top > 0.0
    for p in pts:
        # as the test above (summation order only); atol: a plane whose shear
        # coefficient is zero up to rounding gets ~1e-87 in the reference and
        # 0 in the kernel, which skips zero-shear planes by design
        np.testing.assert_allclose(dmg[p], ref[p], rtol=1e-10, atol=1e-12 * top)
