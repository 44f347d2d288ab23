"""Named bundles of arrays that the kernels take instead of long positional lists.

Each bundle is a named tuple (numba compiles field access to a plain array
access, and the caller passes the same arrays it holds, no copies):

:class:`State`
    What the integrator advances and a checkpoint saves: positions ``x``,
    velocities ``v`` (n, 3, world, m and m/s), orientations ``q`` (n, 4, unit
    quaternions body -> world), body-frame angular velocities ``w`` (n, 3,
    rad/s), the forces at the current state ``Fw``, ``Mw`` (n, 3, world force
    N and moment N m about the centre) and ``Mb`` (n, 3, total body-frame
    moment N m), the scalar state ``sc`` (N_SC,), the contact-cylinder hint of
    every contact point ``hint`` (MAX_CONTACT_POINTS n,) int64 and the contact
    and whirl statistics ``cst`` (n, N_CST). Columns: :mod:`layout`.
:class:`Params`
    The model: step ``dt`` (s), per-segment ``seg``, per-joint ``jp``,
    boundary scalars ``bp``, top-section properties ``topp``, the top anchor
    ``anchor`` (10,), the top-drive speed table ``tab_t``/``tab_w`` (s, rad/s),
    wall / friction / bit parameters ``cpar``, the well path nodes
    ``node_md``/``node_pos``/``node_tan``, the hole cylinders ``wall`` and the
    contact points of each segment ``cp_n`` (rows,) / ``cp`` (rows, MAX_TABLE_POINTS,
    2) read when ``cpar[P_CPTAB]`` is set (:mod:`layout`), and the bending
    stiffness of each segment ``ei`` (rows,) N m^2 for the span correction, and
    the ratio ``mlat`` (rows,) of lateral to steel mass (mud inside and added
    mass) read when ``cpar[P_LATMASS]`` is set.
    ``seg``, ``jp`` and ``topp`` change as the string grows.
:class:`Work`
    What one force evaluation writes (rotation matrices ``R``, world angular
    velocities ``wW``, joint loads ``loads`` (n, 6; row n-1 the top boundary),
    channels ``ch`` (N_CH,)) and the scratch of the kernels: vectors ``vec``
    and 3 x 3 matrices ``mat``, one named row per use (``V_*``, ``M_*`` of
    :mod:`layout`: ``vec[V_J_F]`` is the joint force and nothing else).
:class:`Records`
    The recording request and buffers of one :func:`integrator.advance` call.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from drillfatigue.dynamics.top.connection import N_CC
from drillfatigue.dynamics.core.layout import C_NACT, N_CH, N_MAT, N_VEC, N_VECW
from drillfatigue.dynamics.top.rig import N_BLOCK_P

class State(namedtuple("State", ("x", "v", "q", "w", "Fw", "Mw", "Mb", "sc", "hint", "cst"))):
    """Integrator state (see the module docstring); all float64 but ``hint`` (int64)."""

    __slots__ = ()

    def copy(self) -> State:
        return State(*(a.copy() for a in self))

    def arrays(self) -> dict:
        """The arrays by name (what a checkpoint saves)."""
        return dict(zip(STATE_FIELDS, self, strict=True))

    @property
    def n_active(self) -> int:
        """Active segments now."""
        return int(self.sc[C_NACT])


#: The state's arrays, in order.
STATE_FIELDS: tuple[str, ...] = State._fields


def new_state(x, v, q, w, sc, hint, cst) -> State:
    """A state with zero forces (shapes as the module docstring says)."""
    n = x.shape[0]
    return State(x=x, v=v, q=q, w=w, Fw=np.zeros((n, 3)), Mw=np.zeros((n, 3)),
                 Mb=np.zeros((n, 3)), sc=sc, hint=hint, cst=cst)


Params = namedtuple("Params", ("dt", "seg", "jp", "bp", "topp", "anchor", "tab_t", "tab_w",
                               "cpar", "node_md", "node_pos", "node_tan", "wall", "cp_n",
                               "cp", "ei", "mlat"))

#: one force evaluation's outputs and the kernels' scratch: ``vec`` (N_VEC, N_VECW) and
#: ``mat`` (N_MAT, 3, 3), one named row per use (``V_*``, ``M_*`` of :mod:`layout`). Few
#: arrays on purpose: numba passes a bundle's arrays one by one at every call.
#: the rig boundaries (:func:`boundaries.rig_step`): connection controls now and one
#: step later, a block parameter vector for the connection's velocity override
RigWork = namedtuple("RigWork", ("cc", "cc1", "bpar"))
Work = namedtuple("Work", ("R", "wW", "loads", "ch", "vec", "mat", "rig"))

#: ``counts``: rows written to buf_l, buf_c, buf_k, the loads samples with spans whose
#: span correction was handled locally (a buckled span: none in it, the chain cut
#: there), the number of such spans, and the samples with no span solved (all zero)
Records = namedtuple("Records", ("sel", "every_l", "buf_l", "every_c", "buf_c", "every_k",
                                 "buf_k", "counts", "info"))
#: length of Records.info: [step, segment, value] of a failure
N_INFO = 3


def new_work(n: int, n_ch: int = N_CH) -> Work:
    """Work arrays for ``n`` allocated segment rows and ``n_ch`` channels (``N_CH``, or
    ``N_CH_RIG`` with the rig boundaries)."""
    return Work(R=np.zeros((n, 3, 3)), wW=np.zeros((n, 3)), loads=np.zeros((n, 6)),
                ch=np.zeros(n_ch), vec=np.zeros((N_VEC, N_VECW)), mat=np.zeros((N_MAT, 3, 3)),
                rig=RigWork(np.zeros(N_CC), np.zeros(N_CC), np.zeros(N_BLOCK_P)))


def new_records(sel: np.ndarray, every: tuple[int, ...], rows: tuple[int, ...],
                n: int, n_ch: int = N_CH, span: bool = False) -> Records:
    """Recording buffers: loads of the joints ``sel`` (``span``: and their span-bending
    correction, 2 more columns per joint after the 6 loads of all), channels, kinematics
    of ``n`` rows.

    A channel row is [time, ch[0:N_CH], kinetic energy, work in, dissipated] followed,
    with ``n_ch > N_CH`` (the rig boundaries), by ``ch[N_CH:n_ch]``."""
    width = 1 + (8 if span else 6) * sel.size
    return Records(sel=sel, every_l=int(every[0]), buf_l=np.zeros((rows[0], width)),
                   every_c=int(every[1]), buf_c=np.zeros((rows[1], 4 + n_ch)),
                   every_k=int(every[2]), buf_k=np.zeros((rows[2], 1 + 8 * n)),
                   counts=np.zeros(6, dtype=np.int64), info=np.zeros(N_INFO))

