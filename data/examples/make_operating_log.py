"""Regenerate ``operating_log.csv`` (synthetic; see README.md in this folder)."""

from pathlib import Path

import numpy as np
import pandas as pd

t = np.arange(0, 7200 + 1, 60.0)
rng = np.random.default_rng(3)
rpm = np.where(t < 1800, 120.0, np.where(t < 3600, 150.0, 100.0)) + rng.normal(0, 2, t.size)
wob = np.where(t < 1800, 80.0, np.where(t < 3600, 110.0, 60.0)) + rng.normal(0, 3, t.size)
rop = np.where(t < 1800, 18.0, np.where(t < 3600, 25.0, 12.0)) + rng.normal(0, 0.5, t.size)
md = 600.0 + np.concatenate([[0.0], np.cumsum(rop[:-1] * np.diff(t) / 3600.0)])
pd.DataFrame({"time_s": t, "bit_md_m": md.round(3), "rpm": rpm.round(1), "wob_kN": wob.round(1),
              "rop_m_per_h": rop.round(2)}).to_csv(Path(__file__).with_name("operating_log.csv"),
                                                  index=False)
