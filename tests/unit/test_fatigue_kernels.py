"""Kernel module hygiene and the multi-plane kernel against a per-plane loop."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np

import drillfatigue.fatigue.kernels as K
from drillfatigue.fatigue.critical_plane import CriterionParams, plane_damage, plane_grid
from drillfatigue.fatigue.rainflow import find_cycles_indexed
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import SCF, Section, surface_coefficients


def test_kernel_module_imports_only_numpy_numba_math() -> None:
    tree = ast.parse(Path(K.__file__).read_text(encoding="utf-8"))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            names.add((node.module or "").split(".")[0])
    assert names <= {"__future__", "numpy", "numba", "math"}


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
        ca, cb, _ = prm.constants(crit)
        sig, tau = cs @ L.T, ct @ L.T
        ref = np.zeros_like(dmg)
        for p in range(0, 36, 5):
            for j in range(len(planes)):
                tj = planes.c[j, 0] * sig[p] + planes.c[j, 1] * tau[p]
                nj = planes.n[j, 0] * sig[p] + planes.n[j, 1] * tau[p]
                i0, i1, cnt = find_cycles_indexed(tj, residue)
                dt = np.abs(tj[i1] - tj[i0])
                snmax = np.maximum(nj[i0], nj[i1])
                if crit == "findley":
                    seq = cb * (dt / 2 + ca * snmax)
                else:
                    seq = ca * (dt / 2 + cb * np.maximum(snmax, 0))
                ref[p, j] = np.sum(cnt / curve.cycles_to_failure(2 * np.maximum(seq, 0)))
            # exact counting either way: only summation order differs
            np.testing.assert_allclose(dmg[p], ref[p], rtol=1e-10)
