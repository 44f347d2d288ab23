"""``contact`` section of params.yaml: penalty wall contact and contact-point placement.

Kernel: :mod:`drillfatigue.dynamics.contact.wall` (docs/model.md#contact). Choice of
the defaults (see that module's docstring): k_c = 5e7 N/m keeps the contact
spring softer than the joint springs, so the explicit step stays set by the
joints (``contact.stable_dt(k_c, m_min)`` gives the contact limit), while the
penetration under a 10 kN side force is 0.2 mm, far below the clearance.
Damping 20 % of critical for the mass carried by a contact point.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from drillfatigue.config.base import StrictModel


class ContactConfig(StrictModel):
    """Settings of the ``contact`` section. Units: SI unless the field name says otherwise.

    Attributes
    ----------
    enabled : bool
        Wall contact on/off (off: the string passes through the wall; for
        checks only). Default on.
    k_c_N_per_m : float
        Penalty stiffness, 1e4..1e11 N/m. Default 5e7.
    damping_ratio : float
        Fraction of critical damping of the contact dash-pot,
        ``c_c = 2 zeta sqrt(k_c m)`` with m the mass carried by the contact
        point; 0..1, default 0.2 (docs/model.md: 10-30 %).
    c_c_N_s_per_m : float or None
        Fixed dash-pot value instead of ``damping_ratio`` (N s/m), >= 0.
    points : str
        Contact points per segment: ``string`` (default: the points of the
        string's components below the growing top segment: every tool joint
        at the tool-joint radius, stabilizer blades, centre upsets, and extra
        body points no further apart than the chord/sag rule of
        :mod:`drillfatigue.string.contacts`; the top segment keeps its two
        ends), ``ends`` (its two end points) or ``ends_and_middle`` (plus its
        centre).
    tool_joints : bool
        Add a contact point at each tool joint with the tool-joint radius.
    chord_fraction : float
        With ``points: string``: the share f of the radial clearance a
        straight segment may pass through the inside of a bend unseen
        between two contact points (spacing <= sqrt(8 f c / kappa) for the
        well's largest curvature kappa, :mod:`drillfatigue.string.contacts`);
        0 < f <= 1, default 0.25.
    span_bending : bool
        Record the span-bending correction (the bending of the pipe's own
        weight between the contact points in the wall,
        :mod:`drillfatigue.dynamics.span.record`) at the recorded joints as
        ``span_bending_x_Nm`` / ``span_bending_y_Nm`` in ``loads.parquet``;
        the fatigue chain adds it to the joint moment. Default on
        (docs/bending.md); its supports are the contact points, so it is
        meant with ``points: string`` (tool joints and stabilizers).
    span_dynamic : bool
        The span correction takes its distributed load through each span's
        first bending mode (a single degree of freedom per segment, static
        gain 1, :mod:`drillfatigue.dynamics.span.modal`) instead of
        quasi-statically: a wall impact of a few milliseconds bends the span
        by the factor omega tau of its quasi-static moment, and rings down
        at the span's frequency. Default on (docs/bending.md#dynamic-span-response);
        off: the quasi-static correction at each sample.
    span_damping_min : float
        The least modal damping ratio of the span filter (the segment's mud
        drag gives it otherwise): 0 <= zeta < 0.95, default 0.05.
    deepest_point : bool
        Each segment with three or more contact points also tests, every
        step, the point of its axis furthest out towards the wall between
        them (the vertex of the parabola through the outermost tested point
        and its neighbours, :func:`drillfatigue.dynamics.contact.wall.deepest_point`),
        so that the wall holds a chord in a bend everywhere, not only at the
        points; the span recorder takes it as a support where it touches.
        Default on (docs/bending.md).

    The hole's cylinder chain and its resampling are set in the ``well``
    section (``drillfatigue.well.build_wellbore``), not here.
    """

    enabled: bool = True
    k_c_N_per_m: float = Field(5e7, ge=1e4, le=1e11)
    damping_ratio: float = Field(0.2, ge=0.0, le=1.0)
    c_c_N_s_per_m: float | None = Field(None, ge=0.0, le=1e9)
    points: Literal["ends", "ends_and_middle", "string"] = "string"
    tool_joints: bool = True
    chord_fraction: float = Field(0.25, gt=0.0, le=1.0)
    span_bending: bool = True
    span_dynamic: bool = True
    span_damping_min: float = Field(0.05, ge=0.0, lt=0.95)
    deepest_point: bool = True
