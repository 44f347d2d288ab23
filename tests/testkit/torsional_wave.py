"""A distributed torsional wave model of a drill string off bottom: the reference for stick-slip.

The model of Aarsnes & Shor (Torsional vibrations with bit off bottom: modeling,
characterization and field data validation, J. Petrol. Sci. Eng. 163 (2018) 712-721,
eqs. 1-6), written here from its equations, with this project's wall friction laws
and top-drive PI in place of the paper's. With ``x`` the measured distance down
the string from the quill, ``omega(t, x)`` the angular speed and ``tau(t, x)`` the
torque carried::

    d tau / dt + G J d omega / dx = 0
    rho J d omega / dt + d tau / dx = -c omega - F(omega, x)

``c`` is the torsional mud drag per length (N m s/rad per m) and ``F`` the wall
friction torque per length. The top is the quill, ``omega(t, 0) = omega_TD``, with
``J_TD d omega_TD / dt = T_m - tau(t, 0)`` and the PI motor torque
``T_m = clip(Kp e + Ki int e, +-T_max)``, ``e = omega_set - omega_TD``, whose integral
stops while the output is limited and the error would drive it further (conditional
integration); ``omega_set`` ramps linearly to the set speed. The bit is off bottom:
``tau(t, L) = 0``.

Wall friction. In a straight hole inclined at ``I`` the string lies on the low side
with the buoyed weight across the hole, ``w = (rho_s - rho_m) g A sin I`` per length.
A turning pipe rolls up the wall until gravity's tangential part balances the
friction (``tan phi = mu``), so the wall force is ``w cos phi`` and the friction
torque per length ``r w mu / sqrt(1 + mu^2)`` (the climb; Jansen, J. Sound Vib. 147
(1991)). ``mu`` follows one of two laws of the slip speed ``v = r |omega|``:

``tanh_exp``
    ``mu = tanh(v / v_t) [mu_d + (mu_s - mu_d) exp(-v / v_s)]``: the simulator's
    default law (:mod:`drillfatigue.dynamics.contact.friction`).
``stick_band``
    The inclusion of Aarsnes & Shor (eq. 4): inside the stick band ``v < v_b`` the
    wall holds the string with whatever torque keeps it still, up to the static
    limit (``mu_s``); outside it the dynamic friction (``mu_d``) opposes the motion.
    Aarsnes & Shor state the band as an angular speed ``omega_c`` (1.5 rad/s in their
    published script, 0.5 to 2 rad/s in their fits); here it is a slip speed ``v_b =
    r omega_c``, the form the simulator's law takes.

Discretisation (independent of the simulator's rigid segments): finite volumes of
length at most ``dx_m``, angular speed at the cell centres and torque on the faces
between them (a face joins two half cells in series, so a change of section sits on a
face); a symplectic Euler step (face torques from the twist, then speeds, then
twist), with the mud drag and the wall friction of each cell taken implicitly
(backward Euler in the cell's own speed: a cell's friction can stop it within a step
but never turn it back). ``tanh_exp`` is solved per cell by a safeguarded Newton
iteration; ``stick_band`` in closed form (the torque that stops the cell, clipped at the
static limit). The step is ``cfl`` times the wave's transit time across the
shortest cell.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

G = 9.81


@dataclass(frozen=True)
class Section:
    """A uniform length of tube, SI."""

    length_m: float
    od_m: float
    id_m: float

    @property
    def area_m2(self) -> float:
        return math.pi / 4.0 * (self.od_m**2 - self.id_m**2)

    @property
    def polar_m4(self) -> float:
        return math.pi / 32.0 * (self.od_m**4 - self.id_m**4)


@dataclass(frozen=True)
class WaveWell:
    """A string off bottom in a straight inclined hole, top drive and wall friction (SI).

    ``sections`` run from the quill down to the bit.
    """

    sections: tuple[Section, ...]
    inclination_deg: float
    rho_steel_kg_per_m3: float = 7850.0
    rho_mud_kg_per_m3: float = 1200.0
    shear_modulus_Pa: float = 79.6e9
    mud_damping_Nms_per_rad_per_m: float = 0.05
    law: str = "tanh_exp"
    mu_s: float = 0.35
    mu_d: float = 0.25
    v_t_m_per_s: float = 1e-3
    v_s_m_per_s: float = 0.05
    v_band_m_per_s: float = 0.05
    climb: bool = True
    td_inertia_kg_m2: float = 10.5**2 * 8.0 + 50.0
    kp_Nms_per_rad: float = 2e4
    ki_Nm_per_rad: float = 4e4
    torque_limit_Nm: float = 50e3
    rpm: float = 40.0
    ramp_s: float = 5.0
    dx_m: float = 10.0
    cfl: float = 0.5

    def cells(self) -> dict[str, np.ndarray]:
        """Cell lengths, inertias, radii, static wall torque per length and the face stiffnesses."""
        h, jp, r, wl = [], [], [], []
        sin_i = math.sin(math.radians(self.inclination_deg))
        for s in self.sections:
            n = max(1, math.ceil(s.length_m / self.dx_m - 1e-9))
            h += [s.length_m / n] * n
            jp += [s.polar_m4] * n
            r += [s.od_m / 2.0] * n
            wl += [(self.rho_steel_kg_per_m3 - self.rho_mud_kg_per_m3) * G * s.area_m2 * sin_i] * n
        h_a, jp_a = np.array(h), np.array(jp)
        gj = self.shear_modulus_Pa * jp_a
        # face 0: quill to the first centre; face i: centre i-1 to centre i (half cells in series)
        k = np.empty(h_a.size)
        k[0] = gj[0] / (0.5 * h_a[0])
        k[1:] = 1.0 / (0.5 * h_a[:-1] / gj[:-1] + 0.5 * h_a[1:] / gj[1:])
        return {"h": h_a, "inertia": self.rho_steel_kg_per_m3 * jp_a * h_a, "r": np.array(r),
                "w": np.array(wl), "k": k,
                "wave_speed": np.full(h_a.size, math.sqrt(self.shear_modulus_Pa / self.rho_steel_kg_per_m3))}

    def static_wall_torque_Nm(self) -> float:
        """Torque that holds the whole string still against the static wall friction, N m."""
        c = self.cells()
        return float((c["r"] * c["w"] * c["h"]).sum() * _climb(self.mu_s, self.climb))


def _climb(mu: float | np.ndarray, climb: bool) -> float | np.ndarray:
    return mu / np.sqrt(1.0 + mu * mu) if climb else mu


def _mu_tanh_exp(v: np.ndarray, w: WaveWell) -> np.ndarray:
    return np.tanh(v / w.v_t_m_per_s) * (w.mu_d + (w.mu_s - w.mu_d) * np.exp(-v / w.v_s_m_per_s))


def _dmu_tanh_exp(v: np.ndarray, w: WaveWell) -> np.ndarray:
    th = np.tanh(v / w.v_t_m_per_s)
    ex = np.exp(-v / w.v_s_m_per_s)
    return ((1.0 - th * th) / w.v_t_m_per_s * (w.mu_d + (w.mu_s - w.mu_d) * ex)
            - th * (w.mu_s - w.mu_d) * ex / w.v_s_m_per_s)


def _friction_tanh_exp(om: np.ndarray, b: np.ndarray, a: np.ndarray, hm: np.ndarray, r: np.ndarray,
                       w: WaveWell) -> np.ndarray:
    """Solve ``a x + hm f(r|x|) sign(x) = b`` per cell, f the climb-scaled tanh_exp coefficient.

    ``hm`` is ``dt r w h / I`` (the friction's speed change per unit coefficient). The
    root lies between 0 and ``b / a`` (friction never turns a cell back); Newton steps
    from the cell's last speed, bisection where a step leaves the bracket.
    """
    s = np.sign(b)
    bb = np.abs(b)
    lo = np.zeros_like(bb)
    hi = bb / a
    x = np.clip(np.abs(om), lo, hi)
    for _ in range(60):
        v = r * x
        mu = _mu_tanh_exp(v, w)
        dmu = _dmu_tanh_exp(v, w) * r
        if w.climb:
            q = 1.0 + mu * mu
            f = mu / np.sqrt(q)
            df = dmu / (q * np.sqrt(q))
        else:
            f, df = mu, dmu
        g = a * x + hm * f - bb
        lo = np.where(g < 0.0, x, lo)
        hi = np.where(g >= 0.0, x, hi)
        xn = x - g / (a + hm * df)
        bad = (xn < lo) | (xn > hi) | ~np.isfinite(xn)
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        if np.all(np.abs(xn - x) <= 1e-12 + 1e-10 * np.abs(x)):
            x = xn
            break
        x = xn
    return s * x


def simulate_wave(w: WaveWell, t_end_s: float, sample_s: float = 0.005) -> dict[str, np.ndarray]:
    """Integrate the model from rest; returns ``t, omega_bit, omega_top, torque_surface``.

    Sampled every ``sample_s``; ``omega_bit`` is the speed of the lowest cell,
    ``torque_surface`` the PI's motor torque.
    """
    c = w.cells()
    h, inertia, r, wl, k = c["h"], c["inertia"], c["r"], c["w"], c["k"]
    n = h.size
    dt = w.cfl * float((h / c["wave_speed"]).min())
    n_steps = int(round(t_end_s / dt))
    every = max(1, int(round(sample_s / dt)))
    a = 1.0 + dt * w.mud_damping_Nms_per_rad_per_m * h / inertia
    hm = dt * r * wl * h / inertia
    s_lim = hm * _climb(w.mu_s, w.climb)  # static limit as a speed change per step
    d_lim = hm * _climb(w.mu_d, w.climb)
    om_band = w.v_band_m_per_s / r
    target = w.rpm * math.pi / 30.0
    twist = np.zeros(n)  # twist of face i: angle above it less the angle below (face 0: quill)
    om = np.zeros(n)
    om_td = 0.0
    z = 0.0
    m = n_steps // every + 1
    out = np.zeros((m, 4))
    j = 0
    tq = np.zeros(n + 1)
    for step in range(n_steps):
        t = step * dt
        ws = target * min(t / w.ramp_s, 1.0) if w.ramp_s > 0.0 else target
        tq[:n] = k * twist
        # top drive: PI with conditional integration, then the quill's speed
        e = ws - om_td
        z_new = z + e * dt
        u = w.kp_Nms_per_rad * e + w.ki_Nm_per_rad * z_new
        if (u > w.torque_limit_Nm and e > 0.0) or (u < -w.torque_limit_Nm and e < 0.0):
            z_new = z
            u = w.kp_Nms_per_rad * e + w.ki_Nm_per_rad * z_new
        u = min(max(u, -w.torque_limit_Nm), w.torque_limit_Nm)
        z = z_new
        om_td_new = om_td + dt * (u - tq[0]) / w.td_inertia_kg_m2
        # cells: elastic torques explicit, mud drag and wall friction implicit
        b = om + dt * (tq[:n] - tq[1:]) / inertia
        if w.law == "tanh_exp":
            om_new = _friction_tanh_exp(om, b, a, hm, r, w)
        elif w.law == "stick_band":
            stuck = np.abs(om) < om_band
            stop = np.clip(b, -s_lim, s_lim)  # the speed change the wall may take out
            slide = np.sign(b) * np.minimum(np.abs(b), d_lim)
            om_new = (b - np.where(stuck, stop, slide)) / a
        else:
            raise ValueError(f"unknown friction law {w.law!r} (allowed: tanh_exp, stick_band)")
        # twist from the new speeds (symplectic Euler)
        twist[0] += dt * (om_td_new - om_new[0])
        twist[1:] += dt * (om_new[:-1] - om_new[1:])
        om, om_td = om_new, om_td_new
        if (step + 1) % every == 0:
            out[j] = (t + dt, om[-1], om_td, u)
            j += 1
    out = out[:j]
    return {"t": out[:, 0], "omega_bit": out[:, 1], "omega_top": out[:, 2], "torque_surface": out[:, 3]}
