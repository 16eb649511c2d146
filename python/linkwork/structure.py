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
    their ``types`` whose rows it holds, and its ``coordinates`` (column names)."""

    kind: str
    bodies: tuple[str, ...]
    constraints: tuple[str, ...]
    types: tuple[str, ...]
    coordinates: tuple[str, ...]

    def __str__(self) -> str:
        joints = ", ".join(f"{n} ({t})" for n, t in zip(self.constraints, self.types))
        return f"{self.kind}: {', '.join(self.bodies) or '-'} by {joints}"


@dataclass(frozen=True)
class Structure:
    """``groups`` in solving order (each needs only earlier ones); ``redundant``: the
    constraints of rows no coordinate is left for (structurally redundant); ``free``:
    coordinates no row determines (freedoms the drivers leave)."""

    groups: tuple[Group, ...]
    redundant: tuple[str, ...]
    free: tuple[str, ...]

    @classmethod
    def from_raw(cls, raw: dict[str, Any]) -> Structure:
        groups = tuple(
            Group(
                str(g["kind"]),
                tuple(g["bodies"]),
                tuple(g["constraints"]),
                tuple(g["types"]),
                tuple(g["coordinates"]),
            )
            for g in raw["groups"]
        )
        return cls(groups, tuple(dict.fromkeys(raw["redundant"])), tuple(raw["free"]))

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
        if len(self.groups) > limit:
            lines.append(f"    ... {len(self.groups) - limit} more")
        if self.redundant:
            lines.append(f"  structurally redundant  rows of {', '.join(self.redundant[:limit])}")
        if self.free:
            lines.append(f"  not determined          {', '.join(self.free[:limit])}")
        return "\n".join(lines)
