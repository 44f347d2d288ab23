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
    ``node_md``/``node_pos``/``node_tan`` and the hole cylinders ``wall``.
    ``seg``, ``jp`` and ``topp`` change as the string grows.
:class:`Work`
    What one force evaluation writes (rotation matrices ``R``, world angular
    velocities ``wW``, joint loads ``loads`` (n, 6; row n-1 the top boundary),
    channels ``ch`` (N_CH,)) and the scratch of each submodel, one named
    array per use, grouped per room: :class:`RotorWork`, :class:`JointWork`,
    :class:`DriveWork`, :class:`BitWork`, :class:`WallWork`, :class:`GrowthWork`.
:class:`Records`
    The recording request and buffers of one :func:`integrator.advance` call.
"""

from collections import namedtuple

import numpy as np

from drillfatigue.dynamics.connection import N_CC
from drillfatigue.dynamics.layout import C_NACT, N_CH, WALL_INFO_SIZE
from drillfatigue.dynamics.rig import N_BLOCK_P

STATE_FIELDS = ("x", "v", "q", "w", "Fw", "Mw", "Mb", "sc", "hint", "cst")


class State(namedtuple("State", STATE_FIELDS)):
    """Integrator state (see the module docstring); all float64 but ``hint`` (int64)."""

    __slots__ = ()

    def copy(self) -> "State":
        return State(*(a.copy() for a in self))

    def arrays(self) -> dict:
        """The arrays by name (what a checkpoint saves)."""
        return dict(zip(STATE_FIELDS, self, strict=True))

    @property
    def n_active(self) -> int:
        """Active segments now."""
        return int(self.sc[C_NACT])


def new_state(x, v, q, w, sc, hint, cst) -> State:
    """A state with zero forces (shapes as the module docstring says)."""
    n = x.shape[0]
    return State(x=x, v=v, q=q, w=w, Fw=np.zeros((n, 3)), Mw=np.zeros((n, 3)),
                 Mb=np.zeros((n, 3)), sc=sc, hint=hint, cst=cst)


Params = namedtuple("Params", ("dt", "seg", "jp", "bp", "topp", "anchor", "tab_t", "tab_w",
                               "cpar", "node_md", "node_pos", "node_tan", "wall"))

#: free rotation of a rigid body (:func:`rigid.free_rotation`): two quaternions
RotorWork = namedtuple("RotorWork", ("qa", "qb"))
#: one joint (:func:`joints.joint_force`): relative, half and mid quaternions, the
#: joint frame, the force and moments it returns, its energy and damper power,
#: and the velocity of the growing top segment's lower end
JointWork = namedtuple("JointWork", ("qr", "qh", "qm", "Rm", "f", "m_lo", "m_up", "energy",
                                     "v_up"))
#: the top drive (:func:`boundaries.top_joint`): drive angle quaternion, drive
#: orientation and its matrix, drive angular velocity, velocity and attachment point
DriveWork = namedtuple("DriveWork", ("qz", "q", "R", "w", "v", "p"))
#: the bit guide (:func:`boundaries.bit_guide`): path point and tangent at the
#: rock face, bit-face offset and velocity, guide force, path point and tangent at
#: the bit's own depth, [TOB, ROP] of the bit law
BitWork = namedtuple("BitWork", ("pos", "tan", "dx", "dv", "f", "p2", "t2", "out"))
#: wall contact (:func:`contact.wall_contact`): wall_force's info, the contact
#: point, segment axis, Karnopp's other force, the wall force and its moment,
#: Karnopp's linear and angular acceleration estimates, the whirl direction
#: (unit radial offset, 3, and its length)
WallWork = namedtuple("WallWork", ("info", "x", "axis", "f_other", "force", "moment", "a_lin",
                                   "alpha", "whirl"))
#: growth (:mod:`growth`): world angular velocity of the old top, lever arm,
#: velocities of the split-off piece and of the new top, old centre, two
#: quaternions and a rotation vector, and the ends of the two merged segments
GrowthWork = namedtuple("GrowthWork", ("w", "r", "v_piece", "xc", "v_top", "q", "q2", "theta",
                                       "low_end", "top_end"))
#: the rig boundaries (:func:`boundaries.rig_step`): connection controls now and one
#: step later, a block parameter vector for the connection's velocity override
RigWork = namedtuple("RigWork", ("cc", "cc1", "bpar"))
Work = namedtuple("Work", ("R", "wW", "loads", "ch", "rotor", "joint", "drive", "bit", "wall",
                           "growth", "rig"))

Records = namedtuple("Records", ("sel", "every_l", "buf_l", "every_c", "buf_c", "every_k",
                                 "buf_k", "counts", "info"))
#: length of Records.info: [step, segment, value] of a failure
N_INFO = 3


def new_work(n: int, n_ch: int = N_CH) -> Work:
    """Work arrays for ``n`` allocated segment rows and ``n_ch`` channels (``N_CH``, or
    ``N_CH_RIG`` with the rig boundaries)."""
    def v3() -> np.ndarray:
        return np.zeros(3)

    def q4() -> np.ndarray:
        return np.zeros(4)

    return Work(
        R=np.zeros((n, 3, 3)), wW=np.zeros((n, 3)), loads=np.zeros((n, 6)), ch=np.zeros(n_ch),
        rotor=RotorWork(q4(), q4()),
        joint=JointWork(q4(), q4(), q4(), np.zeros((3, 3)), v3(), v3(), v3(), np.zeros(2), v3()),
        drive=DriveWork(q4(), q4(), np.zeros((3, 3)), v3(), v3(), v3()),
        bit=BitWork(v3(), v3(), v3(), v3(), v3(), v3(), v3(), np.zeros(2)),
        wall=WallWork(np.zeros(WALL_INFO_SIZE), v3(), v3(), v3(), v3(), v3(), v3(), v3(),
                      np.zeros(4)),
        growth=GrowthWork(v3(), v3(), v3(), v3(), v3(), q4(), q4(), v3(), v3(), v3()),
        rig=RigWork(np.zeros(N_CC), np.zeros(N_CC), np.zeros(N_BLOCK_P)),
    )


def new_records(sel: np.ndarray, every: tuple[int, int, int], rows: tuple[int, int, int],
                n: int, n_ch: int = N_CH) -> Records:
    """Recording buffers: loads of the joints ``sel``, channels, kinematics of ``n`` rows.

    A channel row is [time, ch[0:N_CH], kinetic energy, work in, dissipated] followed,
    with ``n_ch > N_CH`` (the rig boundaries), by ``ch[N_CH:n_ch]``."""
    return Records(sel=sel, every_l=int(every[0]), buf_l=np.zeros((rows[0], 1 + 6 * sel.size)),
                   every_c=int(every[1]), buf_c=np.zeros((rows[1], 4 + n_ch)),
                   every_k=int(every[2]), buf_k=np.zeros((rows[2], 1 + 8 * n)),
                   counts=np.zeros(3, dtype=np.int64), info=np.zeros(N_INFO))

