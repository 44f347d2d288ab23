"""Column layout of the packed parameter and state arrays shared by the kernels.

Plain integer constants (numba treats module-level ints as compile-time
constants). Where a block holds another module's vector (a law's parameters, the
rig's block and top-drive vectors) its length comes from that module and the
offsets after it are computed, never typed. The packers of
:mod:`drillfatigue.dynamics.run.model` build the arrays with these indices; the
kernels read them. The arrays travel in the bundles of
:mod:`drillfatigue.dynamics.core.bundles`.
"""

from drillfatigue.dynamics.bit.laws import N_PARAMS as N_BIT_PARAMS
from drillfatigue.dynamics.contact.friction.registry import N_PARAMS as N_FRICTION_PARAMS
from drillfatigue.dynamics.top.connection import N_PHASES
from drillfatigue.dynamics.top.rig import N_BLOCK_P, N_BLOCK_S, N_TD_P, N_TD_S

# seg[i, :] -- per-segment parameters, shape (n, N_SEG)
S_M = 0      # mass (kg)
S_IT = 1     # transverse inertia about the centre (kg m^2)
S_IA = 2     # axial (polar) inertia (kg m^2)
S_H = 3      # half length (m)
S_W = 4      # buoyed weight (N), along +z (world, down)
S_CL = 5     # lateral mud damping (N s/m)
S_CA = 6     # axial mud damping (N s/m)
S_CRL = 7    # rotational mud damping about transverse axes (N m s)
S_CRA = 8    # rotational mud damping about the axis (N m s)
S_RC = 9     # contact radius at the segment ends (m): tool joints / stabilizer blades
S_RB = 10    # body contact radius (m): the middle contact point
S_CC = 11    # contact dash-pot per contact point (N s/m)
N_SEG = 12

# wall[c, :] -- the hole as a chain of straight cylinders (from drillfatigue.well)
W_P0 = 0     # 0..2: start point of the axis (m, world)
W_AX = 3     # 3..5: unit axis
W_LEN = 6    # length (m)
W_RAD = 7    # hole radius (m)
N_WALL = 8

# cpar -- wall contact and friction parameters, packed by the contact/friction layer.
# cpar[P_ON] == 0 switches wall contact off. The two law blocks take the length
# their registries derive; every offset after them follows.
P_ON = 0
P_KC = 1         # penalty stiffness k_c (N/m)
P_FMODEL = 2     # friction law id (drillfatigue.dynamics.contact.friction.registry)
P_NPTS = 3       # contact points per segment: 2 (ends) or 3 (ends and middle)
P_BITLAW = 4     # 0: given TOB tanh(omega/WREF), prescribed ROP; 1: bit_response law
P_BITMODEL = 5   # bit law id (drillfatigue.dynamics.bit.laws)
P_FP = 6                         # friction parameters (friction.registry.N_PARAMS)
P_BP = P_FP + N_FRICTION_PARAMS  # bit parameters (bit.laws.N_PARAMS)
P_CPTAB = P_BP + N_BIT_PARAMS    # 1: segments below the top use their own contact points (Params.cp_n / cp)
P_SPAN = P_CPTAB + 1     # 1: record the span-bending correction at the recorded joints (span.record)
P_LATMASS = P_SPAN + 1   # 1: lateral mass m * Params.mlat[i] across the axis (mud inside, added mass)
P_DEEP = P_LATMASS + 1   # 1: a segment with >= 3 points also tests its deepest point (contact.deepest_point)
P_SPANDYN = P_DEEP + 1   # 1: the span correction takes its load through each span's first mode (span.modal)
P_SPANZ = P_SPANDYN + 1  # the span filter's least damping ratio (contact.span_damping_min)
N_CPAR = P_SPANZ + 1
N_CPAR_MIN = 1

# jp[j, :] -- joint parameters; rows 0..n-2: joint j between segment j and j+1;
# row n-1: the top boundary (top segment <-> top drive / rig)
J_KA = 0
J_KS = 1
J_KB = 2
J_KT = 3
J_CA = 4
J_CS = 5
J_CB = 6
J_CT = 7
N_JP = 8

# bp -- boundary and operation scalars
B_AXMODE = 0     # 0: hook-load force at the top; 1: top held axially by a spring
B_HL = 1         # hook load (N), mode 0
B_BITON = 2      # 1: bit guided on bottom; 0: bit free (off bottom)
B_KBIT = 3       # bit guide stiffness (N/m)
B_CBIT = 4       # bit guide damping (N s/m)
B_TOB = 5        # torque on bit magnitude (N m)
B_WREF = 6       # TOB regularisation speed (rad/s): TOB tanh(omega_bit / WREF)
B_ROP = 7        # rate of penetration (m/s)
B_NLOBE = 8      # number of lobes n
B_LOBE = 9       # lobe amplitude s0 (m)
B_EXT = 10       # growth rate of the top segment (m/s)
B_G = 11         # gravity (m/s^2) -- informative, weights are in seg[:, S_W]
B_ESCALE = 12    # energy scale (J) for the blow-up check
B_TOPAUTO_A = 13  # 1: top axial stiffness follows EA / h_top
B_TOPAUTO_T = 14  # 1: top torsional stiffness follows GJ / h_top
B_ZB = 15        # boundary damping ratio
B_ZJ = 16        # joint damping ratio
B_MD0 = 17       # bit MD at t = 0 (m)
B_DT = 18        # step (s)
B_TOPMODE = 19   # 0: top drive imposes the rpm table; 1: constant torque B_TOPTQ at the top
B_TOPTQ = 20     # applied top torque (N m), mode 1 (ramped over B_TRAMP)
B_TOPLAT = 21    # 1: top held laterally and in tilt (parasitic springs); 0: free
B_LSPLIT = 22    # top segment length (m) at which a segment is split off (drilling)
B_LNOM = 23      # length (m) of a split-off segment
B_LMIN = 24      # top segment length (m) below which it merges with the one below (tripping out)
B_TWIN = 25      # start of the event window (s): after the rpm ramp
B_TRAMP = 26     # top torque ramp time (s), mode 1
B_FREEZE = 27    # 1 during the relaxation pre-run: no ROP / trip, the rock face stays put
# rig boundaries (docs/bending.md; drillfatigue.dynamics.top.rig, .connection, .rockface)
B_RIG = 28       # 1: the block, top drive and rock face of the rig section drive the string
B_BLKMODE = 29   # block mode id (rig.BLOCK_*)
B_TDMODE = 30    # top-drive mode id (rig.TOP_DRIVE_*)
B_CONON = 31     # 1: a connection starts when the block reaches the floor
B_BLKP = 32                      # block parameter vector (rig.BP_*, rig.N_BLOCK_P)
B_TDP = B_BLKP + N_BLOCK_P       # top-drive parameter vector (rig.TP_*, rig.N_TD_P)
B_CONDUR = B_TDP + N_TD_P        # connection phase durations (s), pickup .. tag (N_PHASES)
B_CONPICK = B_CONDUR + N_PHASES  # connection pick-up distance (m)
B_CONSTAND = B_CONPICK + 1       # stand length (m)
B_KROCK = B_CONSTAND + 1         # rock contact stiffness (N/m)
B_CROCK = B_KROCK + 1            # rock contact damping (N s/m)
B_GROWTRAP = B_CROCK + 1   # 1: growth work booked with the force trapezoid (solver.growth_work_trapezoid)
B_IMPBIT = B_GROWTRAP + 1  # 1: the bit torque's damping taken linearly implicit (solver.implicit_bit_torque)
N_BP = B_IMPBIT + 1

# topp -- per-length properties of the extensible top segment (index n-1) and
# section of segment n-2, to rebuild the top rows as the top grows
T_MPL = 0     # mass per length (kg/m)
T_EA = 1
T_EI = 2
T_GJ = 3
T_KGA = 4
T_R2 = 5      # r_o^2 + r_i^2 (m^2)
T_WPL = 6     # buoyed weight per length (N/m)
T_CLPL = 7    # mud damping per length
T_CAPL = 8
T_CRLPL = 9
T_CRAPL = 10
T_H0 = 11     # half length at t = 0 (m)
T_EA2 = 12    # section of segment n-2
T_EI2 = 13
T_GJ2 = 14
T_KGA2 = 15
T_KPAR_S = 16  # top parasitic lateral stiffness (N/m)
T_KPAR_B = 17  # top parasitic tilt stiffness (N m/rad)
T_KA_TOP = 18  # top axial stiffness when fixed by the user (N/m)
T_KT_TOP = 19  # top torsional stiffness when fixed by the user (N m/rad)
N_TOPP = 20

# sc -- scalar state carried between steps (checkpointed)
C_STEP = 0      # step count (float holding an integer)
C_PHID = 1      # top-drive angle (rad)
C_PHIB = 2      # bit rotation angle (rad)
C_WIN = 3       # cumulative work put in by the boundaries (J)
C_DISS = 4      # cumulative dissipated energy (J)
C_HINT = 5      # path search hint
C_MDROCK = 6    # MD of the rock face / bit reference (m)
C_NACT = 7      # active segments (float holding an integer); arrays are sized to the maximum
C_BOUNCE = 8    # bit-bounce count (WOB reaching zero)
C_OFFB = 9      # 1 while the bit is off bottom (bounce), 0 in contact
C_ROPNOW = 10   # current ROP (m/s) from the bit law
C_NSPLIT = 11   # segments added (split off the top)
C_NMERGE = 12   # segments merged (tripping out)
C_GUARD = 13    # 1 once tripping out stopped at the minimum string length
N_SC = 14
# rig state: only with the rig boundaries (bp[B_RIG] == 1), sc then has N_SC_RIG entries
C_BLK = N_SC                  # block state (rig.BS_*, rig.N_BLOCK_S)
C_TD = C_BLK + N_BLOCK_S       # top-drive state (rig.TS_*, rig.N_TD_S)
C_CON = C_TD + N_TD_S          # start times of the connection phases and their end (connection)
C_CONP = C_CON + N_PHASES + 1  # connection parameters [pickup_m, stand_length_m, 0]
C_NSTAND = C_CONP + 3   # stands added (connections completed up to the stand)
C_SHIFTED = C_NSTAND + 1  # 1 once the block travel shift of the current connection is applied
C_VGROW = C_SHIFTED + 1   # rate (m/s) at which the string below the rotary grows this step (block speed)
C_CONPH = C_VGROW + 1     # connection phase now (connection.PH_*)
C_TSET = C_CONPH + 1      # top-drive speed set-point now (rad/s)
N_SC_RIG = C_TSET + 1

# cst[i, :] -- per-segment contact / whirl statistics (state, checkpointed)
CS_ONT = 0      # contact onset time (s), -1 if never
CS_FMAX = 1     # largest normal force (N), sum over the segment's points
CS_IMP = 2      # time integral of the normal force (N s)
CS_TCON = 3     # time in contact (s)
CS_N = 4        # current normal force (N), sum over points
CS_D = 5        # current largest distance of a contact point from the hole centre (m)
CS_ORB = 6      # orbit angle of the centre about the hole axis, summed over the window (rad)
CS_ORBABS = 7   # sum of |d orbit angle| over the window (rad)
CS_TH = 8       # previous orbit angle (rad)
CS_THOK = 9     # 1 when CS_TH is valid
CS_SPIN = 10    # spin angle about the hole axis, summed over the window (rad)
CS_ONMD = 11    # bit MD at contact onset (m)
# the span filter (span_dynamics): running impulse of the dynamic transverse load since
# the last loads sample (3, world, N s) and its duration (s); the filtered load (3, N)
# and its rate (3, N/s); 1 once the filter runs
CS_SQA = 12
CS_SQT = 15
CS_SQF = 16
CS_SQD = 19
CS_SQON = 22
N_CST = 23

# ch -- channels computed with the forces
H_TSURF = 0     # surface torque (N m)
H_HOOK = 1      # hook load (N)
H_WOB = 2       # weight on bit (N)
H_TOB = 3       # torque on bit (N m)
H_TOPRPM = 4    # top-drive speed (rpm)
H_BITRPM = 5    # bit speed (rpm)
H_BITMD = 6     # bit MD (m)
H_ROP = 7       # ROP (m/s)
H_PE = 8        # spring + boundary potential energy (J)
H_PG = 9        # gravity potential energy (J)
H_PDISS = 10    # dissipated power (W)
H_PIN = 11      # power put in by the boundaries (W)
H_NCON = 12     # segments in wall contact
H_FCMAX = 13    # largest segment normal force now (N)
H_NSEG = 14     # active segments
N_CH = 15
# channels of the rig boundaries: the recorder appends them to the channel table only
# with the rig on; they live past N_CH in ch (ch has N_CH_RIG entries)
H_BLOCK = 15    # block travel below the top of its travel (m)
H_BLOCKV = 16   # block velocity (m/s, > 0 lowering)
H_TOPSTR = 17   # string top above the top anchor (rotary), m (< 0: below)
H_CONPH = 18    # connection phase
N_CH_RIG = 19

# work.vec[r, :] -- scratch vectors of the kernels, one row per use (row width N_VECW;
# a use reads the first 2, 3, 4, 15 or MAX_TABLE_POINTS entries)
# rows 0-4: free
V_J_F = 5          # joint force on the lower body (N, world)
V_J_MLO = 6        # joint moment on the lower body (N m, world)
V_J_MUP = 7        # joint moment on the upper body (N m, world)
V_J_ED = 8         # [spring energy (J), damper power (W)] of the last joint
V_J_VUP = 9        # velocity of the growing top segment's lower end (m/s)
V_D_QZ = 10        # boundaries.top_joint: drive angle quaternion
V_D_Q = 11         # drive orientation
V_D_W = 12         # drive angular velocity (rad/s, world)
V_D_V = 13         # drive attachment velocity (m/s)
V_D_P = 14         # drive attachment point (m)
V_B_POS = 15       # boundaries.bit_guide: path point at the rock face (m)
V_B_TAN = 16       # path tangent there
V_B_DX = 17        # bit face minus rock target (m)
V_B_DV = 18        # its velocity (m/s)
V_B_F = 19         # guide force on the bit (N)
V_B_P2 = 20        # path point at the bit's own depth, then the bit face offset from it
V_B_T2 = 21        # path tangent at the bit's own depth
V_B_OUT = 22       # [TOB (N m), ROP (m/s)] of the bit law
V_W_INFO = 23      # contact.wall_force's info (WALL_INFO_SIZE)
V_W_X = 24         # contact point on the centre line (m)
V_W_AX = 25        # segment axis
V_W_FO = 26        # Karnopp's other force at the point (N)
V_W_F = 27         # wall force (N)
V_W_M = 28         # its moment about the centre (N m)
V_W_ALIN = 29      # Karnopp pre-pass: linear acceleration (m/s^2)
V_W_ALPHA = 30     # Karnopp pre-pass: angular acceleration (rad/s^2)
V_W_WHIRL = 31     # events.track_whirl: unit radial offset (3) and its length (m)
V_G_W = 32         # growth.split_top: world angular velocity of the old top
V_G_R = 33         # lever arm (m)
V_G_VPIECE = 34    # velocity of the split-off piece (m/s)
V_G_XC = 35        # old centre (m)
V_G_VTOP = 36      # velocity of the new top (m/s)
V_G_Q = 37         # relative rotation of the joint below the top (quaternion)
# row 38: free
V_G_TH = 39        # rotation vector of the joint below the top (rad)
V_G_LOW = 40       # growth.merge_top: lower end of the lower segment (m)
V_G_TOP = 41       # upper end of the top segment (m)
V_W_OFF = 42       # contact.wall_contact: offsets of a segment's points (MAX_TABLE_POINTS, m)
V_W_G = 43         # their axis offsets from the wall, distance from the centre line - R (m)
V_B_IMP = 44       # boundaries.bit_guide: [dTOB/domega (N m s/rad), >= 0] for implicit_bit_damping
N_VEC = 45
N_VECW = 32

# work.mat[r, :, :] -- scratch 3 x 3 matrices
# row 0: free
M_D_R = 1          # drive rotation (boundaries.top_joint)
N_MAT = 2

# wall contact points: at most MAX_CONTACT_POINTS per segment; the contact-cylinder
# hint of point p of segment i is hint[MAX_CONTACT_POINTS * i + p]
MAX_CONTACT_POINTS = 3
# with cpar[P_CPTAB] = 1 a segment below the top has cp_n[i] <= MAX_TABLE_POINTS points
# (cp[i, k] = [offset from the centre along e3 (m, > 0 towards the bit), radius (m)]);
# the hint of its point k is hint[MAX_CONTACT_POINTS * rows + MAX_TABLE_POINTS * i + k]
# (rows: allocated segment rows; -1: not located yet, start from the segment's first hint)
MAX_TABLE_POINTS = 32

# info[:] written by contact.wall_force for one contact point
WI_DELTA = 0     # penetration (m), > 0 in contact
WI_NX = 1        # 1..3: outward unit normal from the hole centre line
WI_S = 4         # position along the located cylinder's axis (m)
WI_DIST = 5      # distance from the hole centre line (m)
WI_N = 6         # normal force (N)
WI_SLIP = 7      # slip speed at the surface contact point (m/s)
WI_VS = 8        # 8..10: slip velocity (m/s)
WI_FO = 11       # 11..13: tangential part of the other force (N, scratch)
WI_CYL = 14      # cylinder located (the next hint), or -1 beyond the chain's ends
WALL_INFO_SIZE = 15
