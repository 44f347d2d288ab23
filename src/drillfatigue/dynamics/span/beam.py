"""Span bending between supports: the Python layer over the beam kernels.

:func:`continuous_beam_moments` checks its input, calls the kernels of
:mod:`drillfatigue.dynamics.span.bending` (continuous beam-column on rigid
supports, three-moment equation; see that module for the solution and where
it stops being valid) and returns the moments over the supports, at the read
points and the mid-span deflections. :func:`spans_from_supports` turns
support positions along the string into spans; :func:`pipe_frame_moments`
resolves moments fixed in the hole into the pipe-fixed frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from drillfatigue.dynamics.span import bending as K
from drillfatigue.errors import InputError

_ENDS = {"pinned": K.END_PINNED, "clamped": K.END_CLAMPED}


@dataclass(frozen=True)
class BeamMoments:
    """Result of :func:`continuous_beam_moments` (SI).

    Attributes
    ----------
    support_Nm : ndarray, shape (n_span + 1, 2)
        Moment vectors (M_x, M_y) over the supports, N m (sign convention of
        ``loads.parquet``: M_x > 0 stretches the +y fibre).
    read_Nm : ndarray, shape (n_read, 2)
        Moment vectors at the read points, N m.
    midspan_deflection_m : ndarray, shape (n_span,)
        Mid-span deflection of each span, m (compare with the clearance).
    """

    support_Nm: np.ndarray
    read_Nm: np.ndarray
    midspan_deflection_m: np.ndarray


def _vec(name: str, v: object, n: int | None = None) -> np.ndarray:
    a = np.ascontiguousarray(np.asarray(v, dtype=np.float64))
    if a.ndim != 1 or (n is not None and a.size != n):
        raise InputError(name, f"must be a 1-D array{'' if n is None else f' of {n} values'}, "
                         f"got shape {a.shape}", "one value per span")
    if not np.all(np.isfinite(a)):
        raise InputError(name, "must be finite", "finite numbers")
    return a


def continuous_beam_moments(span_m: Sequence[float] | np.ndarray,
                            ei_Nm2: Sequence[float] | np.ndarray | float,
                            q_N_per_m: np.ndarray,
                            axial_N: Sequence[float] | np.ndarray | float = 0.0,
                            ends: tuple[str, str] = ("pinned", "pinned"),
                            read_span: Sequence[int] | np.ndarray | None = None,
                            read_x_m: Sequence[float] | np.ndarray | None = None,
                            support_offsets_m: np.ndarray | None = None) -> BeamMoments:
    """Moments of a continuous beam-column on rigid supports under span loads.

    With ``support_offsets_m`` the supports stand at different heights (the
    settlement terms of the three-moment equation,
    :func:`drillfatigue.dynamics.span.bending.support_moments_settled`).

    Parameters
    ----------
    span_m : array, shape (n_span,)
        Span lengths, m (> 0).
    ei_Nm2 : float or array, shape (n_span,)
        Bending stiffness, N m^2 (> 0).
    q_N_per_m : array, shape (n_span, 2) or (2,)
        Uniform transverse load per span in a cross-section frame, N/m.
    axial_N : float or array, shape (n_span,)
        Effective axial force, N (tension > 0).
    ends : (str, str)
        End conditions at the first and last support: ``pinned`` or ``clamped``.
    read_span, read_x_m : arrays, shape (n_read,), optional
        Read points: span index and distance from that span's first support.
    support_offsets_m : array, shape (n_span + 1, 2), optional
        Offset of each support in the frame of ``q`` (component k along load
        component k), m; none: level supports.

    Returns
    -------
    BeamMoments

    Raises
    ------
    InputError
        Bad shapes or values, or a span in compression beyond its Euler load
        (the beam solution does not hold: the span lies on the wall).
    """
    span = _vec("span_m", span_m)
    n = span.size
    if n == 0 or np.any(span <= 0.0):
        raise InputError("span_m", "must hold at least one span, each > 0", "span_m > 0")
    ei = _vec("ei_Nm2", np.broadcast_to(np.asarray(ei_Nm2, dtype=np.float64), (n,)), n)
    if np.any(ei <= 0.0):
        raise InputError("ei_Nm2", "must be > 0", "EI > 0")
    ax = _vec("axial_N", np.broadcast_to(np.asarray(axial_N, dtype=np.float64), (n,)), n)
    q = np.asarray(q_N_per_m, dtype=np.float64)
    q = np.ascontiguousarray(np.broadcast_to(q, (n, 2)) if q.shape == (2,) else q)
    if q.shape != (n, 2) or not np.all(np.isfinite(q)):
        raise InputError("q_N_per_m", f"must be finite with shape ({n}, 2), got {q.shape}",
                         "one (q_x, q_y) per span")
    if len(ends) != 2 or any(e not in _ENDS for e in ends):
        raise InputError("ends", f"unknown end conditions {ends!r}", "pinned, clamped")
    work = np.empty((n + 1, 6))
    sup = np.empty((n + 1, 2))
    if support_offsets_m is None:
        st = K.support_moments(span, ei, ax, q, _ENDS[ends[0]], _ENDS[ends[1]], work, sup)
    else:
        d = _offsets(support_offsets_m, n + 1)
        st = K.support_moments_settled(span, ei, ax, q, d, _ENDS[ends[0]], _ENDS[ends[1]],
                                       work, sup)
    if st == K.STATUS_SPAN_BUCKLED:
        raise InputError("axial_N", "a span in compression is at or beyond its Euler load "
                         "pi^2 EI/L^2: it lies on the wall, add supports",
                         "compression below 0.998 pi^2 EI/L^2 per span")
    if st != K.STATUS_OK:
        raise InputError("span_m", f"continuous-beam solve failed (status {st})",
                         "positive spans and stiffness")
    if read_span is None:
        rs = np.zeros(0, dtype=np.int64)
        rx = np.zeros(0)
    else:
        rs = np.ascontiguousarray(np.asarray(read_span, dtype=np.int64))
        rx = _vec("read_x_m", read_x_m if read_x_m is not None else [], rs.size)
    rd = np.empty((rs.size, 2))
    if K.moments_at(span, ei, ax, q, sup, rs, rx, rd) != K.STATUS_OK:
        raise InputError("read_x_m", "read point outside its span",
                         "0 <= read_span < n_span and 0 <= read_x_m <= span")
    defl = np.empty(n)
    K.midspan_deflection(span, ei, ax, q, sup, defl)
    return BeamMoments(sup, rd, defl)


def _offsets(d_m: object, n_sup: int) -> np.ndarray:
    d = np.ascontiguousarray(np.asarray(d_m, dtype=np.float64))
    if d.shape != (n_sup, 2) or not np.all(np.isfinite(d)):
        raise InputError("support_offsets_m", f"must be finite with shape ({n_sup}, 2), got "
                         f"{d.shape}", "one offset pair per support")
    return d


def spans_from_supports(support_s_m: Sequence[float] | np.ndarray) -> np.ndarray:
    """Span lengths between sorted support positions along the string, m.

    Raises InputError when positions are not strictly increasing.
    """
    s = _vec("support_s_m", support_s_m)
    if s.size < 2 or np.any(np.diff(s) <= 0.0):
        raise InputError("support_s_m", "needs >= 2 strictly increasing positions",
                         "s_0 < s_1 < ...")
    return np.diff(s)


def pipe_frame_moments(M_hole_Nm: np.ndarray, angle_rad: np.ndarray) -> np.ndarray:
    """Moments (n, 2) fixed in a non-turning frame, seen in the pipe-fixed frame
    turned by ``angle_rad`` (n,) about the pipe axis."""
    M = np.ascontiguousarray(np.asarray(M_hole_Nm, dtype=np.float64).reshape(-1, 2))
    a = np.ascontiguousarray(np.broadcast_to(np.asarray(angle_rad, dtype=np.float64),
                                             (M.shape[0],)))
    out = np.empty_like(M)
    K.to_pipe_frame(M, a, out)
    return out


def chain_span_moments(support_s_m: np.ndarray, segment_bounds_m: np.ndarray,
                       ei_Nm2: np.ndarray, axial_N: np.ndarray, q_N_per_m: np.ndarray,
                       read_s_m: np.ndarray, ends: tuple[str, str] = ("pinned", "pinned"),
                       support_offsets_m: np.ndarray | None = None
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Span-bending moments of a segment chain at read points (see the kernel
    :func:`drillfatigue.dynamics.span.bending.chain_span_moments`).

    A span in compression at or beyond its Euler load is handled locally: the
    chain is cut there (pinned over the cut span's supports), the cut span gets
    no correction and the other spans are solved as the chain without it.

    Parameters
    ----------
    support_s_m : array (n_sup,)
        Support positions from the bit, m, strictly increasing.
    segment_bounds_m : array (n_seg + 1,)
        Segment ends from the bit, m.
    ei_Nm2, axial_N : array (n_seg,)
    q_N_per_m : array (n_seg, 2)
        Transverse load per length in a common cross-section frame.
    read_s_m : array (n_read,)
        Where the moments are wanted (e.g. the recorded joints), m from the bit.
    ends : (str, str)
    support_offsets_m : array (n_sup, 2), optional
        Offset of each support in the frame of ``q``, m (none: level supports;
        :func:`drillfatigue.dynamics.span.bending.chain_span_moments_settled`).

    Returns
    -------
    support_Nm : ndarray, shape (n_sup, 2)
    read_Nm : ndarray, shape (n_read, 2)
    span_cut : ndarray of int64, shape (n_sup - 1,)
        0 (``drillfatigue.status.OK``) for a solved span, else the status code
        of why it got no correction (``SPAN_BUCKLED``, ``BAD_SPAN``,
        ``SINGULAR``).
    """
    sup = _vec("support_s_m", support_s_m)
    bounds = _vec("segment_bounds_m", segment_bounds_m)
    n_seg = bounds.size - 1
    ei = _vec("ei_Nm2", ei_Nm2, n_seg)
    ax = _vec("axial_N", axial_N, n_seg)
    q = np.ascontiguousarray(np.asarray(q_N_per_m, dtype=np.float64))
    if q.shape != (n_seg, 2):
        raise InputError("q_N_per_m", f"must have shape ({n_seg}, 2), got {q.shape}",
                         "one (q_x, q_y) per segment")
    rd = _vec("read_s_m", read_s_m)
    if len(ends) != 2 or any(e not in _ENDS for e in ends):
        raise InputError("ends", f"unknown end conditions {ends!r}", "pinned, clamped")
    m = max(sup.size - 1, 0)
    sup_M = np.empty((sup.size, 2))
    read_M = np.empty((rd.size, 2))
    cut = np.zeros(m, dtype=np.int64)
    chain = K.SegmentChain(bounds, ei, ax, q)
    spans = K.Spans(np.empty(m), np.empty(m), np.empty(m), np.empty((m, 2)))
    e0, e1 = _ENDS[ends[0]], _ENDS[ends[1]]
    if support_offsets_m is None:
        st = K.chain_span_moments(sup, chain, e0, e1, rd, spans, np.empty((sup.size, 6)), sup_M,
                                  read_M, cut)
    else:
        st = K.chain_span_moments_settled(sup, _offsets(support_offsets_m, sup.size), chain, e0,
                                          e1, rd, spans, np.empty((sup.size, 6)), sup_M, read_M,
                                          cut, np.zeros(rd.size, dtype=np.int64))
    if st != K.STATUS_OK:
        raise InputError("support_s_m", f"chain span solve failed (status {st})",
                         "increasing supports inside the segments, EI > 0")
    return sup_M, read_M, cut
