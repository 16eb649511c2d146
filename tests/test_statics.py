"""Statics: the efforts that hold a configuration, and the mechanical advantage."""

from __future__ import annotations

import linkwork as lw


def test_mechanical_advantage_is_the_torque_ratio_of_virtual_work():
    # a load torque on the rocker: the crank torque that holds it is T_out / MA
    m = lw.examples.four_bar(theta0=0.8)
    m.torque("rocker", lw.Constant(-2.0), name="load")
    model = m.compile()
    s = model.statics(0.0)
    ma = s.mechanical_advantage("crank", "rocker")
    assert abs(abs(s.effort("crank_angle")) - 2.0 / ma) <= 1e-10 * 2.0 / ma
