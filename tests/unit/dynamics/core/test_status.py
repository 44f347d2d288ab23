"""The package's one status enumeration and its wrapper: each failure code
becomes a KernelError naming the kernel and what failed; the fatigue kernels
return the enumeration's codes."""

from __future__ import annotations

import numpy as np
import pytest

import drillfatigue.dynamics.core.status as dynamics_status
import drillfatigue.dynamics.span.bending as SB
import drillfatigue.fatigue.kernels as K
import drillfatigue.numba_cache as NC
import drillfatigue.status as S
from drillfatigue.errors import KernelError, raise_for_status

FAILURES = {name: getattr(S, name) for name in (
    "NONFINITE", "BLOWUP", "SPEED", "UNKNOWN_FRICTION", "UNKNOWN_BIT", "UNKNOWN_RIG_MODE",
    "STACK_OVERFLOW", "OUT_OVERFLOW", "BAD_SPAN", "SPAN_BUCKLED", "SINGULAR")}


def test_codes_are_distinct_and_each_failure_has_a_message() -> None:
    codes = [S.OK, *FAILURES.values()]
    assert S.OK == 0 and len(set(codes)) == len(codes)
    assert all(isinstance(c, int) for c in codes)
    assert set(S.MESSAGES) == set(FAILURES.values())


def test_the_dynamics_module_reexports_the_same_codes() -> None:
    assert dynamics_status.OK == S.OK
    for name, code in FAILURES.items():
        if hasattr(dynamics_status, name):
            assert getattr(dynamics_status, name) == code
    assert dynamics_status.MESSAGES is S.MESSAGES


def test_ok_raises_nothing() -> None:
    assert raise_for_status(S.OK, "any_kernel") is None


@pytest.mark.parametrize("name", sorted(FAILURES))
def test_each_failure_code_raises_its_message(name: str) -> None:
    code = FAILURES[name]
    with pytest.raises(KernelError) as info:
        raise_for_status(code, "some_kernel")
    assert str(info.value) == f"some_kernel: {S.MESSAGES[code]} (status {code})"
    assert isinstance(info.value, RuntimeError)  # what the wrappers raised before


def test_an_unknown_code_still_raises_and_names_it() -> None:
    with pytest.raises(KernelError, match=r"k: unknown status code \(status 99\)"):
        raise_for_status(99, "k")


def test_rainflow_kernel_reports_a_short_output_as_minus_out_overflow() -> None:
    y = np.array([0.0, 3.0, 1.0, 2.0, 0.5, 4.0, -1.0])  # closes cycles before the residue
    n = y.size
    big = [np.empty(2 * n + 2, np.int64), np.empty(2 * n + 2, np.int64), np.empty(2 * n + 2)]
    nc = K.rainflow_indexed(y, K.RESIDUE_HALF, *big, np.empty(n + 1, np.int64))
    assert nc >= 2
    short = [np.empty(nc - 1, np.int64), np.empty(nc - 1, np.int64), np.empty(nc - 1)]
    assert K.rainflow_indexed(y, K.RESIDUE_HALF, *short, np.empty(n + 1, np.int64)) == -S.OUT_OVERFLOW


def test_group_push_reports_a_full_stack_as_stack_overflow() -> None:
    sv, sx, sy = np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2))
    ms = np.zeros(1, np.int64)
    assert K._push_group(sv, sx, sy, ms, 0, 1.0, 0.0, 0.0) == S.OK
    assert K._push_group(sv, sx, sy, ms, 0, -2.0, 0.0, 0.0) == S.OK
    assert K._push_group(sv, sx, sy, ms, 0, 3.0, 0.0, 0.0) == S.STACK_OVERFLOW  # a third reversal


def test_span_bending_codes_are_the_enumerations() -> None:
    assert (S.BAD_SPAN, S.SPAN_BUCKLED, S.SINGULAR) == (9, 10, 11)
    assert SB.STATUS_OK == S.OK
    assert SB.STATUS_BAD_SPAN == S.BAD_SPAN
    assert SB.STATUS_SPAN_BUCKLED == S.SPAN_BUCKLED
    assert SB.STATUS_SINGULAR == S.SINGULAR
    # the kernels freeze these numbers: the numba cache key must cover their module
    assert "status.py" in NC.KERNEL_CONSTANT_MODULES


def test_span_kernel_returns_the_enumerations_codes() -> None:
    work = np.empty((3, 6))
    out = np.empty((3, 2))
    q = np.zeros((2, 2))
    ei = np.ones(2)
    assert SB.support_moments(np.array([1.0, 1.0]), ei, np.zeros(2), q, SB.END_PINNED,
                              SB.END_PINNED, work, out) == S.OK
    assert SB.support_moments(np.array([1.0, -1.0]), ei, np.zeros(2), q, SB.END_PINNED,
                              SB.END_PINNED, work, out) == S.BAD_SPAN
    # compression of 1.2 pi^2 EI/L^2 on the second span: beyond its Euler load
    assert SB.support_moments(np.array([1.0, 1.0]), ei, np.array([0.0, -1.2 * np.pi ** 2]), q,
                              SB.END_PINNED, SB.END_PINNED, work, out) == S.SPAN_BUCKLED
