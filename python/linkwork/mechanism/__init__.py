"""Building a mechanism: the `Mechanism` builder (bodies, joints, drivers, loads), its
files, its assembly from pins, the lengths-first builders (`linkwork.build`) and the
textbook examples (`linkwork.examples`). Compiles into a `linkwork.model.Model`."""

from .builder import GROUND, Body, Mechanism

__all__ = ["GROUND", "Body", "Mechanism"]
