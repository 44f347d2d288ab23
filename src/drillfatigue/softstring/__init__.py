"""Soft-string models: quasi-static torque and drag along the string, and buckling onset.

* :mod:`~drillfatigue.softstring.march` -- the soft-string march (Johancsik et al. 1984), kernel and API;
* :mod:`~drillfatigue.softstring.torque_drag` -- torque and drag of a case;
* :mod:`~drillfatigue.softstring.buckling` -- onset loads and margins along the string.
"""
