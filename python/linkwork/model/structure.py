"""The mechanism's structure: groups of coordinates solved together, in solving order."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Group", "Structure"]


@dataclass(frozen=True)
class Group:
    """Coordinates that must be solved together: ``kind`` ("input" for a group holding a
    driver, "one body", "dyad RRR", "dyad RRP", "dyad RPR", "dyad PRP", "dyad RPP",
    "triad", "group"), the moving ``bodies`` it places, the ``constraints`` (names) and
    their ``types`` whose rows it holds, its ``coordinates`` (column names), and the
    ``method`` a sweep solves it by (a closed form and the unknowns it keeps, a Newton
    block, or "general path" when the whole model is solved as one system)."""

    kind: str
    bodies: tuple[str, ...]
    constraints: tuple[str, ...]
    types: tuple[str, ...]
    coordinates: tuple[str, ...]
    method: str = "general path"

    def __str__(self) -> str:
        joints = ", ".join(f"{n} ({t})" for n, t in zip(self.constraints, self.types))
        return f"{self.kind}: {', '.join(self.bodies) or '-'} by {joints}"


@dataclass(frozen=True)
class Structure:
    """``groups`` in solving order (each needs only earlier ones); ``redundant``: the
    constraints of rows no coordinate is left for (structurally redundant); ``free``:
    coordinates no row determines (freedoms the drivers leave); ``fallback``: why a sweep
    solves the whole model as one system instead of group by group (None: it does not)."""

    groups: tuple[Group, ...]
    redundant: tuple[str, ...]
    free: tuple[str, ...]
    fallback: str | None = None

    @classmethod
    def from_raw(cls, raw: dict[str, Any]) -> Structure:
        groups = tuple(
            Group(
                str(g["kind"]),
                tuple(g["bodies"]),
                tuple(g["constraints"]),
                tuple(g["types"]),
                tuple(g["coordinates"]),
                str(g.get("method", "general path")),
            )
            for g in raw["groups"]
        )
        return cls(groups, tuple(dict.fromkeys(raw["redundant"])), tuple(raw["free"]), raw.get("fallback"))

    def counts(self) -> dict[str, int]:
        """How many groups of each kind."""
        out: dict[str, int] = {}
        for g in self.groups:
            out[g.kind] = out.get(g.kind, 0) + 1
        return out

    def report(self, limit: int = 12) -> str:
        """The groups in solving order (the first ``limit``), then what is left over."""
        counts = ", ".join(f"{n} {k}" for k, n in self.counts().items())
        lines = [f"  structure               {len(self.groups)} groups in solving order ({counts})"]
        for i, g in enumerate(self.groups[:limit], 1):
            lines.append(f"    {i}. {g}")
            lines.append(f"       {g.method}")
        if len(self.groups) > limit:
            lines.append(f"    ... {len(self.groups) - limit} more")
        if self.redundant:
            lines.append(f"  structurally redundant  rows of {', '.join(self.redundant[:limit])}")
        if self.free:
            lines.append(f"  not determined          {', '.join(self.free[:limit])}")
        if self.fallback is None:
            lines.append("  solver                  structured: the groups in this order")
        else:
            lines.append(f"  solver                  general (one sparse system): {self.fallback}")
        return "\n".join(lines)
