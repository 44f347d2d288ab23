"""Case 2 drills as a rig does: the autodriller on WOB, the bit law's ROP, a continuous window."""

from __future__ import annotations

import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.config.studies import Case2Config
from drillfatigue.studies import case2


def test_rig_case_has_the_autodriller_and_no_prescribed_rop() -> None:
    cfg = Case2Config(n_samples=1, sample_s=40.0, boundaries="rig")
    d = case2.case_dict(cfg, "profile_1", 480.0, 1)
    assert "rop_m_per_s" not in d["operation"] and "lobe_amplitude_m" not in d["operation"]
    assert d["bit"]["model"] == "yigit_christoforou"
    rig = d["rig"]
    assert rig["block_mode"] == "autodriller"
    assert rig["autodriller"] == {"measurement": "wob", "wob_set_N": 100e3}
    assert rig["rock"]["lobe_amplitude_m"] == cfg.lobe_amplitude_m
    c = case_from_dict(d)  # a valid case: no input the rig cannot use
    assert c.rig is not None and c.rig.effective_inputs()["block"]["initial_travel_m"] == 5.0


def test_prescribed_rop_case_is_the_founding_papers() -> None:
    cfg = Case2Config(boundaries="prescribed_rop")
    d = case2.case_dict(cfg, "profile_1", 480.0, 1)
    assert "rig" not in d
    assert d["operation"]["rop_m_per_s"] == pytest.approx(0.5)
    assert case_from_dict(d).rig is None


def test_a_written_rig_case_reads_back() -> None:
    # the run folder's case.yaml lists every field, defaults included: reading it
    # back (the fatigue chain does, for the mud pressure) must not see the
    # operation's default hook load or lobes as inputs the rig would ignore
    cfg = Case2Config(n_samples=1, sample_s=40.0, boundaries="rig")
    case = case_from_dict(case2.case_dict(cfg, "profile_1", 480.0, 1))
    assert case.rig is not None
    again = case_from_dict(case.model_dump(mode="json"))
    assert again == case
    # an explicit hook load is still refused with the rig
    data = case.model_dump(mode="json")
    data["operation"]["hook_load_N"] = 5e5
    with pytest.raises(ValueError, match="hook_load_N"):
        case_from_dict(data)
