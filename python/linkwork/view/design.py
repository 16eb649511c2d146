"""A synthesized design's pictures with its targets marked: the page, the SVG, the DXF
and the plot of its path, for any design class that inherits `DesignPictures`."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .figures import plot_paths
from .targets import Deviation, Targets, deviation, of_design, sweep_design

if TYPE_CHECKING:
    from linkwork import Results

__all__ = ["DesignPictures"]


class DesignPictures:
    """The pictures of a synthesized design with its targets marked (`of_design`): a
    design class that has ``.model()``, ``.positions`` and ``.coupler_angles`` (and
    ``.precision_times()`` where it knows them) gets these by inheriting it."""

    def targets(self) -> Targets:
        """The design's precision points and poses (`of_design`)."""
        return of_design(self)

    def sweep(self, steps: int = 721) -> Results:
        """The design's model swept over one turn (`sweep_design`)."""
        return sweep_design(self, steps=steps)

    def deviation(self, steps: int = 721) -> Deviation:
        """How far the design's traced point passes from its targets (`deviation`)."""
        return deviation(self.sweep(steps), self)

    def to_html(self, path: Any = None, **options: Any) -> str:
        """The interactive page of `sweep` with the targets marked (`linkwork.view.page.page`;
        ``options`` as it takes them)."""
        return self.sweep().to_html(path, targets=self, **options)

    def to_svg(self, path: Any = None, **options: Any) -> str:
        """The SVG of `sweep` with the targets marked (`linkwork.view.export.svg`)."""
        return self.sweep().to_svg(path, targets=self, **options)

    def to_dxf(self, path: Any, **options: Any) -> None:
        """The DXF of `sweep` with the targets marked (`linkwork.view.export.dxf`)."""
        self.sweep().to_dxf(path, targets=self, **options)

    def plot(self, path: str, **options: Any) -> list[str]:
        """A PNG of the path over the design with the targets marked
        (`linkwork.view.figures.plot_paths`)."""
        return plot_paths(self.sweep(), path, targets=self, **options)
