"""An independent, plain-NumPy implementation of linkwork's formulation, used to check
the engine.

It reads the model description only (``Mechanism.to_dict()`` or the dict itself) and
never imports the engine. Dense matrices, ``np.linalg.solve``, one small class per joint
and driver type (``formulation``), motion laws in ``laws``, assembly and solves in
``model``, and the inverse dynamics (M, Q, Phi_q^T lambda = Q - M qdd, reactions) in
``dynamics`` (``ReferenceModel.inverse_dynamics``, ``sweep_forces``, ``statics``); the
forward dynamics, index 1 with projection, in ``forward`` (``simulate``) and the exact
and published solutions of its benchmarks in ``exact``.
``closed_form`` (also ``linkwork.closed_form``) holds the textbook closed forms of the
four-bar and the offset slider-crank, a check independent of both.

>>> import linkwork as lw
>>> from linkwork.reference import ReferenceModel
>>> m = lw.Mechanism()
>>> crank = m.link("crank", (0, 0), (1, 0))
>>> _ = m.revolute(m.ground, crank, at=(0, 0))
>>> _ = m.drive_angle(crank, lw.Linear(0.0, 2.0))
>>> ref = ReferenceModel(m)
>>> q, qd, qdd = ref.solve(0.5)
>>> round(float(q[2]), 12), round(float(qd[2]), 12)
(1.0, 2.0)
"""

from .forward import simulate
from .laws import check_law, motion_law
from .model import ConvergenceError, ReferenceModel

__all__ = ["ReferenceModel", "ConvergenceError", "motion_law", "check_law", "simulate"]
