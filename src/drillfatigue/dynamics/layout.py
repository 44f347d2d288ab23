"""Column layout of the packed parameter and state arrays shared by the kernels.

Plain integer constants (numba treats module-level ints as compile-time
constants). Python code builds the arrays with these indices; kernels read them.
"""

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
S_RC = 9     # contact radius (m), for the wall contact of the next issue
N_SEG = 10

# wall[c, :] -- the hole as a chain of straight cylinders (from drillfatigue.well)
W_P0 = 0     # 0..2: start point of the axis (m, world)
W_AX = 3     # 3..5: unit axis
W_LEN = 6    # length (m)
W_RAD = 7    # hole radius (m)
N_WALL = 8

# cpar -- wall contact and friction parameters, packed by the contact/friction layer.
# cpar[P_ON] == 0 switches wall contact off (this issue); the remaining layout
# is owned by the contact / friction modules.
P_ON = 0
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
N_BP = 19

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
N_SC = 6

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
N_CH = 12

# status codes returned by the kernels
ST_OK = 0
ST_NONFINITE = 1
ST_BLOWUP = 2
ST_FORCES = 3
