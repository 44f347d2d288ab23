"""A small catalogue of common drill pipe, heavy-weight pipe and collar sizes (field units).

Values are the tabulated ones, in inches and lb/ft as printed; they are
converted to SI only where a component is built (:mod:`drillfatigue.io.tally`).

Drill pipe body
    OD, nominal weight -> wall thickness, ID and plain-end weight: API Spec 5DP
    (2020; formerly Spec 5D), table of drill-pipe dimensions and masses. The
    plain-end weight is ``10.68 (D - t) t`` lb/ft (steel at 0.2833 lb/in^3).
Tool joints
    (pipe size, nominal weight, grade, connection) -> tool-joint OD and ID for
    new drill pipe with its standard weld-on tool joint: API RP 7G (16th ed.,
    1998), table of new drill pipe with tool joints (same data in API Spec
    5DP). The tool-joint OD grows and the bore shrinks with the grade, keeping
    the connection's torsional strength at >= 80 % of the tube's.
Heavy-weight drill pipe
    Conventional (centre-upset) HWDP: tube OD/ID, approximate adjusted weight
    and tool joint as listed in manufacturers' catalogues; API standardises
    the connection (API Spec 7-1) but not the tube, so these are typical
    values.
Drill collars
    OD x bore and the usual connection (API Spec 7-1, standard steel drill
    collars); the weight is API RP 7G's drill-collar formula
    ``2.67 (OD^2 - ID^2)`` lb/ft (steel at 490 lb/ft^3).

Any dimension given in a tally overrides the catalogue's.
"""

from __future__ import annotations

from dataclasses import dataclass

API_5DP = "API Spec 5DP (2020), drill-pipe dimensions and masses"
API_RP7G_TJ = "API RP 7G (16th ed., 1998), new drill pipe with tool joints"
API_RP7G_DC = "API Spec 7-1 collar sizes and connections; weight by API RP 7G's formula"
HWDP_TYPICAL = "typical conventional HWDP (manufacturers' catalogues; API 7-1 connection)"

#: API drill-pipe grades: minimum yield strength in ksi (API Spec 5DP).
API_GRADES: dict[str, int] = {"E-75": 75, "X-95": 95, "G-105": 105, "S-135": 135}


@dataclass(frozen=True)
class PipeBody:
    """Drill-pipe tube of a nominal size and weight (inches, lb/ft)."""

    od_in: float
    nominal_weight_lb_per_ft: float
    wall_in: float
    id_in: float
    plain_end_weight_lb_per_ft: float
    reference: str = API_5DP


@dataclass(frozen=True)
class ToolJoint:
    """Tool joint of a connection: OD and bore (inches)."""

    connection: str
    od_in: float
    id_in: float
    reference: str = API_RP7G_TJ


@dataclass(frozen=True)
class HeavyWeight:
    """Conventional heavy-weight drill pipe (inches, lb/ft)."""

    od_in: float
    id_in: float
    adjusted_weight_lb_per_ft: float
    tool_joint: ToolJoint
    reference: str = HWDP_TYPICAL


#: RP 7G drill-collar weight factor, lb/ft per in^2 of OD^2 - ID^2.
RP7G_COLLAR_FACTOR = 2.67


@dataclass(frozen=True)
class Collar:
    """Steel drill collar: OD x bore (inches) and connection."""

    od_in: float
    id_in: float
    connection: str
    reference: str = API_RP7G_DC

    @property
    def weight_lb_per_ft(self) -> float:
        """RP 7G drill-collar weight ``2.67 (OD^2 - ID^2)``, lb/ft."""
        return RP7G_COLLAR_FACTOR * (self.od_in**2 - self.id_in**2)


#: (OD in, nominal weight lb/ft) -> tube.
DRILL_PIPE: dict[tuple[float, float], PipeBody] = {
    (3.5, 13.3): PipeBody(3.5, 13.30, 0.368, 2.764, 12.31),
    (4.0, 14.0): PipeBody(4.0, 14.00, 0.330, 3.340, 12.93),
    (4.5, 16.6): PipeBody(4.5, 16.60, 0.337, 3.826, 14.98),
    (5.0, 19.5): PipeBody(5.0, 19.50, 0.362, 4.276, 17.93),
    (5.0, 25.6): PipeBody(5.0, 25.60, 0.500, 4.000, 24.03),
    (5.5, 21.9): PipeBody(5.5, 21.90, 0.361, 4.778, 19.81),
    (5.5, 24.7): PipeBody(5.5, 24.70, 0.415, 4.670, 22.54),
    (6.625, 25.2): PipeBody(6.625, 25.20, 0.330, 5.965, 22.19),
}


def _tj(conn: str, od: float, bore: float) -> ToolJoint:
    return ToolJoint(conn, od, bore)


#: (OD in, nominal weight lb/ft, grade, connection) -> tool joint.
TOOL_JOINTS: dict[tuple[float, float, str, str], ToolJoint] = {
    (3.5, 13.3, "E-75", "NC38"): _tj("NC38", 4.75, 2.6875),
    (3.5, 13.3, "X-95", "NC38"): _tj("NC38", 5.0, 2.5625),
    (3.5, 13.3, "G-105", "NC38"): _tj("NC38", 5.0, 2.4375),
    (3.5, 13.3, "S-135", "NC38"): _tj("NC38", 5.0, 2.125),
    (4.5, 16.6, "E-75", "NC46"): _tj("NC46", 6.25, 3.25),
    (4.5, 16.6, "X-95", "NC46"): _tj("NC46", 6.25, 3.0),
    (4.5, 16.6, "G-105", "NC46"): _tj("NC46", 6.25, 2.75),
    (4.5, 16.6, "S-135", "NC46"): _tj("NC46", 6.25, 2.5),
    (5.0, 19.5, "E-75", "NC50"): _tj("NC50", 6.375, 3.75),
    (5.0, 19.5, "X-95", "NC50"): _tj("NC50", 6.625, 3.5),
    (5.0, 19.5, "G-105", "NC50"): _tj("NC50", 6.625, 3.25),
    (5.0, 19.5, "S-135", "NC50"): _tj("NC50", 6.625, 2.75),
    (5.5, 21.9, "E-75", "5-1/2FH"): _tj("5-1/2FH", 7.0, 4.0),
    (5.5, 21.9, "X-95", "5-1/2FH"): _tj("5-1/2FH", 7.0, 3.75),
    (5.5, 21.9, "G-105", "5-1/2FH"): _tj("5-1/2FH", 7.25, 3.5),
    (5.5, 21.9, "S-135", "5-1/2FH"): _tj("5-1/2FH", 7.5, 3.0),
}

#: tube OD in -> conventional HWDP.
HWDP: dict[float, HeavyWeight] = {
    3.5: HeavyWeight(3.5, 2.0625, 25.3, ToolJoint("NC38", 4.75, 2.1875, HWDP_TYPICAL)),
    4.5: HeavyWeight(4.5, 2.75, 41.0, ToolJoint("NC46", 6.25, 2.8125, HWDP_TYPICAL)),
    5.0: HeavyWeight(5.0, 3.0, 49.3, ToolJoint("NC50", 6.5, 3.0625, HWDP_TYPICAL)),
}

#: (OD in, bore in) -> steel drill collar.
COLLARS: dict[tuple[float, float], Collar] = {
    (4.75, 2.25): Collar(4.75, 2.25, "NC35"),
    (6.25, 2.8125): Collar(6.25, 2.8125, "NC46"),
    (6.5, 2.8125): Collar(6.5, 2.8125, "NC46"),
    (6.75, 2.8125): Collar(6.75, 2.8125, "NC50"),
    (8.0, 2.8125): Collar(8.0, 2.8125, "6-5/8REG"),
    (9.5, 3.0): Collar(9.5, 3.0, "7-5/8REG"),
}
