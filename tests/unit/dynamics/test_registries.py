"""The friction and bit-law registries: every registered law is reachable from the
configuration, documented, dispatched to, and its parameter block is where the
registry says.
"""

from __future__ import annotations

import re
import typing
from pathlib import Path

import numpy as np
import pytest

from drillfatigue.config.bit import BitConfig
from drillfatigue.config.friction import FrictionConfig, FrictionModelName
from drillfatigue.dynamics import registries
from drillfatigue.dynamics.bit.laws import kernel as bit_kernel
from drillfatigue.dynamics.bit.laws import registry as bit_registry
from drillfatigue.dynamics.contact.friction import dispatch as friction_dispatch
from drillfatigue.dynamics.contact.friction import registry as friction_registry
from drillfatigue.dynamics.contact.friction.base import N_SHARED
from drillfatigue.dynamics.core import layout as L

ROOT = Path(__file__).resolve().parents[3]
MODEL_MD = (ROOT / "docs" / "model.md").read_text(encoding="utf-8")


def test_the_dispatch_modules_are_written_from_the_registries() -> None:
    assert registries.main(["--check"]) == 0, "run: python -m drillfatigue.dynamics.registries"


def test_every_friction_law_is_a_configuration_choice_and_documented() -> None:
    names = [law.NAME for law in friction_registry.LAWS]
    assert sorted(names) == sorted(typing.get_args(FrictionModelName))
    fields = set(FrictionConfig.model_fields)
    for law in friction_registry.LAWS:
        assert set(law.PARAMS) <= fields, law.NAME
        assert f"(`{law.NAME}`)" in MODEL_MD, f"docs/model.md#friction does not name {law.NAME}"


def test_every_bit_law_is_a_configuration_choice_and_documented() -> None:
    names = sorted(bit_registry.MODEL_IDS)
    assert names == sorted(typing.get_args(BitConfig.model_fields["model"].annotation))
    for law in bit_registry.LAWS:
        assert re.search(rf"\| `{law.NAME}`", MODEL_MD), f"docs/model.md#bit does not name {law.NAME}"
        values = law.pack(BitConfig(model=law.NAME), 1e-3)
        assert len(values) == len(law.PARAMS), law.NAME


def test_offsets_are_derived_and_the_blocks_do_not_overlap() -> None:
    for reg, start in ((friction_registry, N_SHARED), (bit_registry, 0)):
        at = start
        for law, off in zip(reg.LAWS, reg.OFFSETS, strict=True):
            assert off == at
            at += len(law.PARAMS)
        assert reg.N_PARAMS == at
    assert L.P_BP == L.P_FP + friction_registry.N_PARAMS
    assert L.P_CPTAB == L.P_BP + bit_registry.N_PARAMS
    assert L.N_CPAR == L.P_SPANZ + 1


@pytest.mark.parametrize("law_id", range(len(friction_registry.LAWS)))
def test_a_friction_law_chosen_by_name_is_the_one_dispatched(law_id: int) -> None:
    law = friction_registry.LAWS[law_id]
    mid, p = friction_registry.pack_friction_params(FrictionConfig(model=law.NAME))
    assert mid == law_id
    block = friction_registry.law_block(mid, p)
    cfg = FrictionConfig(model=law.NAME)
    assert list(block) == [getattr(cfg, name) for name in law.PARAMS]
    for speed in (0.0, 1e-4, 3e-3, 0.04, 0.5, 3.0):
        got = friction_dispatch.slip_coefficient(mid, p, speed)
        assert got == law.coefficient(p, friction_registry.OFFSETS[mid], speed)
        assert 0.0 <= got <= cfg.mu_static
    assert friction_dispatch.has_stiction(mid) == law.STICTION
    assert friction_dispatch.slip_coefficient(len(friction_registry.LAWS), p, 0.1) == -1.0


@pytest.mark.parametrize("law_id", range(len(bit_registry.LAWS)))
def test_a_bit_law_chosen_by_name_is_the_one_dispatched(law_id: int) -> None:
    law = bit_registry.LAWS[law_id]
    mid, p = bit_registry.pack_bit_params(BitConfig(model=law.NAME), 2e-3)
    assert mid == law_id
    off = bit_registry.OFFSETS[mid]
    for wob, om in ((5e4, 0.3), (1e5, 15.7), (2e5, -2.0)):
        got, want = np.zeros(2), np.zeros(2)
        bit_kernel.bit_response(mid, p, wob, om, got)
        law.response(p, off, wob, om, want)
        assert np.array_equal(got, want)
        assert bit_kernel.bit_torque_slope(mid, p, wob, om) == law.torque_slope(p, off, wob, om)
