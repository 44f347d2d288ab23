"""S-N curves (built on fatpack's endurance curves), mean-stress corrections, grades.

Curves are tabulated as in DNV-RP-C203: log10 N = log10 a - m log10 S with S
the stress range in MPa; stresses enter this module in Pa and are converted
here (``units.MPA_PA``). Every library curve carries a ``reference``.

Library (DNV-RP-C203, April 2016 edition):

* air, Table 2-1: knee at N = 1e7 (m = 3 or 4 above, m = 5 below);
* seawater with cathodic protection, Table 2-2: knee at N = 1e6;
* free corrosion, Table 2-4: single slope m = 3, no knee.

Thread defaults: DNV-RP-C203 section 2.9 guidance for bolts uses F1 for rolled
threads and W3 for cut threads, on the *nominal* stress in the threaded section
(so with these curves set the connection SCFs to 1). The default at a
connection is the local (thread-root) stress with the thread-root SCF on the
smooth base-material curve B1: an engineering assumption, documented in
``config/fatigue.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import fatpack
import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.units import MPA_PA, PSI_PA

ENVIRONMENTS: tuple[str, ...] = ("air", "seawater_cp", "free_corrosion")
MEAN_STRESS_METHODS: tuple[str, ...] = ("none", "goodman", "walker", "swt", "compressive")

# (m1, log a1, m2, log a2, thickness exponent k) in air, Table 2-1
_AIR = {
    "B1": (4.0, 15.117, 5.0, 17.146, 0.0),
    "C": (3.0, 12.592, 5.0, 16.320, 0.05),
    "D": (3.0, 12.164, 5.0, 15.606, 0.20),
    "F1": (3.0, 11.699, 5.0, 14.832, 0.25),
    "W3": (3.0, 10.970, 5.0, 13.617, 0.25),
}
# seawater with cathodic protection, Table 2-2 (log a1; the second slope equals air)
_SWCP_LOGA1 = {"B1": 14.917, "C": 12.192, "D": 11.764, "F1": 11.299, "W3": 10.570}
# free corrosion, Table 2-4 (m = 3 for all classes)
_FC_LOGA = {"B1": 12.436, "C": 12.115, "D": 11.687, "F1": 11.222, "W3": 10.493}
_ALIASES = {"thread_rolled": "F1", "thread_cut": "W3"}

#: Names accepted by :func:`get_curve`.
CURVE_NAMES: tuple[str, ...] = tuple(_AIR) + tuple(_ALIASES)


@dataclass(frozen=True)
class Grade:
    """Drill-pipe steel grade (API Spec 5DP minimum strengths), Pa."""

    name: str
    yield_Pa: float
    tensile_Pa: float
    reference: str = "API Spec 5DP (2020), Table C.4: minimum yield / tensile strength"


GRADES: dict[str, Grade] = {
    "E-75": Grade("E-75", 75_000 * PSI_PA, 100_000 * PSI_PA),
    "X-95": Grade("X-95", 95_000 * PSI_PA, 105_000 * PSI_PA),
    "G-105": Grade("G-105", 105_000 * PSI_PA, 115_000 * PSI_PA),
    "S-135": Grade("S-135", 135_000 * PSI_PA, 145_000 * PSI_PA),
}


def get_grade(name: str) -> Grade:
    """Grade by name; InputError listing the allowed names otherwise."""
    if name not in GRADES:
        raise InputError("fatigue.grade", f"unknown grade {name!r}", ", ".join(GRADES))
    return GRADES[name]


@dataclass(frozen=True)
class SNCurve:
    """Piecewise log-linear S-N curve on stress ranges in MPa.

    Attributes
    ----------
    name : str
    m : tuple of float
        Inverse slopes of the segments, high stress first.
    log_a : tuple of float
        log10 a of each segment (N = a S^-m, S in MPa).
    knees_N : tuple of float
        Cycle numbers at the knees between segments (len(m) - 1 of them).
    cutoff_N : float or None
        Endurance (cut-off) at this N: 1/N = 0 below the matching stress.
    thickness_exponent : float
        k of the thickness correction S (t / t_ref)^k, t > t_ref.
    t_ref_m : float
        Reference thickness, m (25 mm in DNV-RP-C203).
    reference : str
    """

    name: str
    m: tuple[float, ...]
    log_a: tuple[float, ...]
    knees_N: tuple[float, ...] = ()
    cutoff_N: float | None = None
    thickness_exponent: float = 0.0
    t_ref_m: float = 0.025
    reference: str = ""
    _fp: object = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        if len(self.m) != len(self.log_a) or len(self.knees_N) != len(self.m) - 1 \
                or not 1 <= len(self.m) <= 2:
            raise InputError(f"sn_curve {self.name}", "needs 1 or 2 segments with one knee "
                             "between two", "linear, bi-linear or tri-linear (bi-linear + cut-off)")
        if any(not (0.5 <= mi <= 20.0) for mi in self.m):
            raise InputError(f"sn_curve {self.name}.m", f"slopes {self.m} out of range",
                             "0.5 <= m <= 20")
        object.__setattr__(self, "_fp", self._build_fatpack())

    def _build_fatpack(self) -> fatpack.endurance.AbstractEnduranceCurve:
        Nc = 10.0 ** self.log_a[0]
        if len(self.m) == 1:
            c = fatpack.LinearEnduranceCurve(1.0)
            c.Nc, c.m = Nc, self.m[0]
            return c
        if self.cutoff_N is None:
            c = fatpack.BiLinearEnduranceCurve(1.0)
        else:
            c = fatpack.TriLinearEnduranceCurve(1.0)
            c.Nl = float(self.cutoff_N)
        c.Nc, c.m1, c.m2, c.Nd = Nc, self.m[0], self.m[1], float(self.knees_N[0])
        return c

    @property
    def fatpack_curve(self) -> fatpack.endurance.AbstractEnduranceCurve:
        """The fatpack endurance curve (stress ranges in MPa)."""
        return self._fp  # type: ignore[return-value]

    def thickness_factor(self, thickness_m: float | None) -> float:
        """DNV-RP-C203 eq. (2.4.3) factor (t/t_ref)^k for t > t_ref, else 1."""
        if thickness_m is None or thickness_m <= self.t_ref_m:
            return 1.0
        return (thickness_m / self.t_ref_m) ** self.thickness_exponent

    def cycles_to_failure(self, S_range_Pa: np.ndarray | float) -> np.ndarray:
        """N(S) for stress ranges in Pa (inf below a cut-off; S = 0 gives inf)."""
        S = np.atleast_1d(np.asarray(S_range_Pa, dtype=np.float64)) / MPA_PA
        N = np.full(S.shape, np.inf)
        pos = S > 0.0
        if np.any(pos):
            with np.errstate(over="ignore", divide="ignore"):
                N[pos] = self.fatpack_curve.get_endurance(S[pos])
        return N

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """(seg_S_low, seg_m, seg_inv_a, S_cut) in MPa for the numba kernels."""
        c = self.fatpack_curve
        if len(self.m) == 1:
            return (np.array([0.0]), np.array([self.m[0]]),
                    np.array([1.0 / c.Nc]), 0.0)
        Sd = c.Sd
        inv_a1 = 1.0 / (c.Nc * c.Sc ** c.m1)
        inv_a2 = 1.0 / (c.Nd * Sd ** c.m2)
        S_cut = float(c.Sl) if self.cutoff_N is not None else 0.0
        return (np.array([Sd, 0.0]), np.array([c.m1, c.m2]), np.array([inv_a1, inv_a2]), S_cut)


def _dnv(name: str, environment: str) -> SNCurve:
    m1, la1, m2, la2, k = _AIR[name]
    if environment == "air":
        return SNCurve(name, (m1, m2), (la1, la2), (1e7,), None, k,
                       reference=f"DNV-RP-C203 (2016) Table 2-1, {name} in air; N(knee) = 1e7")
    if environment == "seawater_cp":
        return SNCurve(name, (m1, m2), (_SWCP_LOGA1[name], la2), (1e6,), None, k,
                       reference=f"DNV-RP-C203 (2016) Table 2-2, {name} in seawater with "
                                 "cathodic protection; N(knee) = 1e6")
    return SNCurve(name, (3.0,), (_FC_LOGA[name],), (), None, k,
                   reference=f"DNV-RP-C203 (2016) Table 2-4, {name} free corrosion; m = 3")


def get_curve(name: str, environment: str = "air") -> SNCurve:
    """Library curve by name and environment.

    Parameters
    ----------
    name : str
        One of :data:`CURVE_NAMES` (``thread_rolled`` = F1, ``thread_cut`` = W3).
    environment : {'air', 'seawater_cp', 'free_corrosion'}
        ``free_corrosion`` is also the option for corrosive mud.
    """
    if environment not in ENVIRONMENTS:
        raise InputError("fatigue.environment", f"unknown environment {environment!r}",
                         ", ".join(ENVIRONMENTS))
    key = _ALIASES.get(name, name)
    if key not in _AIR:
        raise InputError("fatigue.sn_curve", f"unknown S-N curve {name!r}",
                         ", ".join(CURVE_NAMES) + " or a user-defined curve")
    return _dnv(key, environment)


def user_curve(m1: float, log_a1: float, m2: float | None = None, knee_N: float | None = None,
               cutoff_N: float | None = None, name: str = "user",
               reference: str = "user-defined") -> SNCurve:
    """Linear, bi-linear or tri-linear user curve (S in MPa)."""
    if m2 is None:
        return SNCurve(name, (m1,), (log_a1,), reference=reference)
    if knee_N is None:
        raise InputError(f"sn_curve {name}.knee_N", "required for a bi-linear curve", "> 0")
    la2 = math.log10(knee_N) + m2 * (log_a1 - math.log10(knee_N)) / m1
    return SNCurve(name, (m1, m2), (log_a1, la2), (knee_N,), cutoff_N, reference=reference)


def correct_mean_stress(S_range: np.ndarray, S_mean: np.ndarray, method: str,
                        ultimate_Pa: float, walker_gamma: float = 0.5,
                        compressive_alpha: float = 0.6) -> np.ndarray:
    """Equivalent zero-mean stress range (fatpack's correction helpers).

    Parameters
    ----------
    S_range, S_mean : ndarray, shape (n,)
        Ranges and means, Pa.
    method : {'none', 'goodman', 'walker', 'swt', 'compressive'}
        Goodman uses the ultimate strength and only tensile means (a
        compressive mean is not credited; conservative); Walker/SWT give zero
        for cycles entirely in compression (S_max <= 0); ``compressive``
        reduces the compressive part of the range by ``compressive_alpha``
        (DNV-RP-C203 section 2.5).

    References
    ----------
    Dowling, Calhoun, Arcari, FFEMS 32 (2009) 163-179 (Walker); DNV-RP-C203.
    """
    S = np.asarray(S_range, dtype=np.float64)
    Sm = np.asarray(S_mean, dtype=np.float64)
    if method == "none":
        return S.copy()
    if method == "goodman":
        return fatpack.find_goodman_equivalent_stress(S, np.maximum(Sm, 0.0), ultimate_Pa)
    if method in ("walker", "swt"):
        out = np.zeros_like(S)
        ok = (Sm + S / 2.0) > 0.0
        if np.any(ok):
            if method == "walker":
                out[ok] = fatpack.find_walker_equivalent_stress(S[ok], Sm[ok], walker_gamma)
            else:
                out[ok] = fatpack.find_swt_equivalent_stress(S[ok], Sm[ok])
        return out
    if method == "compressive":
        return fatpack.find_reduced_compressive_stress(S, Sm, compressive_alpha)
    raise InputError("fatigue.mean_stress", f"unknown mean-stress correction {method!r}",
                     ", ".join(MEAN_STRESS_METHODS))
