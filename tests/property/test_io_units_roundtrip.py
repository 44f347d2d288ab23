"""Property: a value written in any exact field unit reads back to the same SI float."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.io.headers import UNIT_SPELLINGS, exact_factor, field_text, si_from_text

EXACT_UNITS = [(q, u) for q, table in UNIT_SPELLINGS.items() for u in table
               if exact_factor(q, u, "x") is not None]


@settings(max_examples=400, deadline=None)
@given(value=st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300,
                       max_value=1e300),
       unit=st.sampled_from(EXACT_UNITS))
def test_field_text_round_trip_is_exact(value: float, unit: tuple[str, str]) -> None:
    quantity, name = unit
    text = field_text(value, quantity, name)
    back = si_from_text(text, quantity, name, "x")
    assert back == value  # bit for bit (-0.0 reads back as 0.0, equal as a float)
