"""Degrees of freedom two ways (Gruebler's count and the rank of Phi_q) and redundant rows."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Mobility"]


@dataclass(frozen=True)
class Mobility:
    """Mobility of a model at one configuration ``q``.

    ``gruebler_dof``: 3 per moving body minus the joint rows; ``dof``: what the rank of
    the joints' Phi_q leaves; ``*_driven``: the same with the drivers' rows. Where they
    differ, ``explanation`` says why. ``redundancies``: (singular value, ((constraint,
    share), ...)) per dependent row combination; ``nearest``: the combination closest to
    dependent when there is none; ``free_motions``: ((coordinate, share), ...) per motion
    left free with the drivers held.
    """

    q: np.ndarray = field(repr=False)
    n_bodies: int
    n_coords: int
    joint_rows: int
    driver_rows: int
    gruebler_dof: int
    gruebler_dof_driven: int
    rank_joints: int
    rank: int
    dof: int
    dof_driven: int
    singular_values: np.ndarray = field(repr=False)
    redundancies: tuple[tuple[float, tuple[tuple[str, float], ...]], ...]
    nearest: tuple[float, tuple[tuple[str, float], ...]] | None
    free_motions: tuple[tuple[tuple[str, float], ...], ...]
    explanation: tuple[str, ...]

    @classmethod
    def from_raw(cls, raw: dict[str, Any]) -> Mobility:
        def dep(d: Any) -> tuple[float, tuple[tuple[str, float], ...]]:
            return float(d[0]), tuple((str(n), float(s)) for n, s in d[1])

        return cls(
            q=np.asarray(raw["q"]),
            n_bodies=int(raw["n_bodies"]),
            n_coords=int(raw["n_coords"]),
            joint_rows=int(raw["joint_rows"]),
            driver_rows=int(raw["driver_rows"]),
            gruebler_dof=int(raw["gruebler_dof"]),
            gruebler_dof_driven=int(raw["gruebler_dof_driven"]),
            rank_joints=int(raw["rank_joints"]),
            rank=int(raw["rank"]),
            dof=int(raw["dof"]),
            dof_driven=int(raw["dof_driven"]),
            singular_values=np.asarray(raw["singular_values"]),
            redundancies=tuple(dep(d) for d in raw["redundancies"]),
            nearest=None if raw["nearest"] is None else dep(raw["nearest"]),
            free_motions=tuple(tuple((str(c), float(s)) for c, s in m) for m in raw["free_motions"]),
            explanation=tuple(raw["explanation"]),
        )

    @property
    def redundant(self) -> bool:
        return bool(self.redundancies)

    def report(self) -> str:
        """A readable multi-line report."""
        lines = [
            f"  moving bodies           {self.n_bodies} ({self.n_coords} coordinates)",
            f"  rows                    {self.joint_rows} from joints, {self.driver_rows} from drivers",
            f"  degrees of freedom      Gruebler {self.gruebler_dof}, rank {self.dof} "
            f"(rank of the joints' rows {self.rank_joints} of {self.joint_rows})",
            f"  left with the drivers   Gruebler {self.gruebler_dof_driven}, rank {self.dof_driven}",
        ]
        if self.nearest is not None:
            sigma, who = self.nearest
            lines.append(
                f"  smallest singular value {sigma:.2e} (scaled; near 0: near a singular configuration), "
                f"among {', '.join(n for n, _ in who[:4])}"
            )
        lines += [f"  ! {e}" for e in self.explanation]
        return "\n".join(lines)
