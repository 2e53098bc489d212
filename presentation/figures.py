"""Shared matplotlib style for the reproduction figures: engineering plots, headless (Agg).

Every figure is titled with the paper's figure number, has labelled axes with units and a
legend where more than one curve shares an axis, and is saved as PNG (120 dpi) and SVG.
"""

from __future__ import annotations

import base64
import html
import io
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from armlab.files import write_file

if TYPE_CHECKING:
    from matplotlib.typing import RcKeyType

__all__ = ["DPI", "Figures", "draw_chain_3d", "new_figure", "save", "save_png", "set_equal_3d", "wrap_title"]

DPI = 120

_STYLE: dict[RcKeyType, Any] = {
    "font.size": 9,
    "axes.titlesize": 10,
    "figure.titlesize": 11,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linestyle": ":",
    "lines.linewidth": 1.4,
    "axes.prop_cycle": None,  # filled in below
    "svg.fonttype": "none",
}


def new_figure(title: str, nrows: int = 1, ncols: int = 1, size: tuple[float, float] = (7.0, 4.5),
               projection: str | None = None, **kwargs: Any) -> tuple[Any, Any]:
    """A titled figure with ``nrows × ncols`` axes (``projection="3d"`` for 3-D), drawn by Agg.

    The figure is not pyplot's: making one never opens a window, blocks, or changes the user's backend, and a
    notebook shows it when it is a cell's value (``plt.close`` on it is harmless).
    """
    import matplotlib.pyplot as plt
    from cycler import cycler
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    colors = ["#1f5fa8", "#c0392b", "#2e8b57", "#8e44ad", "#d68910", "#5d6d7e", "#17a2b8"]
    style: dict[RcKeyType, Any] = {**_STYLE, "axes.prop_cycle": cycler(color=colors)}
    plt.rcParams.update(style)  # the whole process plots in this one style
    subplot_kw = {"projection": projection} if projection else None
    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)  # fig.canvas.draw() lays it out (the scheme's labels are placed on the final layout)
    axes = fig.subplots(nrows, ncols, squeeze=False, subplot_kw=subplot_kw, **kwargs)
    fig.suptitle(wrap_title(title, size[0]), fontweight="bold")
    return fig, axes if nrows * ncols > 1 else axes[0, 0]


def wrap_title(title: str, width_inches: float) -> str:
    """``title`` broken into lines that fit a figure ``width_inches`` wide in the bold title font.

    A bold character of the 11 pt title is about 0.62 em wide on average, so a line holds about
    ``width · 72 / (11 · 0.62)`` characters; explicit line breaks are kept.
    """
    chars = max(20, int(width_inches * 72 / (_STYLE["figure.titlesize"] * 0.62)))
    return "\n".join(textwrap.fill(line, chars) for line in title.splitlines())


def save(fig: Any, stem: Path) -> list[Path]:
    """Save ``fig`` as ``stem.png`` and ``stem.svg`` and close it; returns both paths."""
    import matplotlib.pyplot as plt

    stem = Path(stem)
    paths = [stem.with_suffix(".png"), stem.with_suffix(".svg")]
    fig.savefig(paths[0], dpi=DPI)
    fig.set_layout_engine("none")  # the SVG keeps the layout the PNG's drawing computed (no second layout pass)
    fig.savefig(paths[1])
    plt.close(fig)
    return paths


class Figures(dict[str, Any]):
    """Matplotlib figures by file name (``"joints.png"`` → figure): a ``dict``, which a Jupyter cell whose value it
    is draws — each figure inline as a PNG under its name (:meth:`_repr_html_`) — rather than listing
    ``<Figure …>`` objects."""

    def __repr__(self) -> str:
        return f"<Figures: {', '.join(self)}>"

    def _repr_html_(self) -> str:
        """Jupyter's view: each figure as an inline PNG (base64) under its name."""

        parts = []
        for name, fig in self.items():
            buffer = io.BytesIO()
            fig.savefig(buffer, format="png", dpi=DPI)
            data = base64.b64encode(buffer.getvalue()).decode("ascii")
            parts.append(f'<figure><figcaption>{html.escape(name)}</figcaption>'
                         f'<img src="data:image/png;base64,{data}" alt="{html.escape(name)}"></figure>')
        return "<div>" + "".join(parts) + "</div>"


def save_png(fig: Any, path: Path) -> str:
    """Save ``fig`` as a PNG at ``path`` atomically (:func:`~armlab.files.write_file`), close it; its name."""
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    plt.close(fig)
    write_file(path, buffer.getvalue())
    return Path(path).name


#: The shortest side of a 3-D plot's box, as a share of its longest: a flat cloud (a planar arm) keeps some depth.
MIN_BOX_SIDE = 0.35


def set_equal_3d(ax: Any, points: ArrayLike) -> None:
    """Equal scale on the three axes of a 3-D plot around ``points`` (N, 3), in a box shaped like them.

    Each axis spans the points' extent on it plus 10 % (at least :data:`MIN_BOX_SIDE` of the longest), and the
    box's sides are in proportion to the spans: a metre is as long on every axis, and a tall or flat set of
    points fills the picture instead of sitting small in a cube.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    centre = (p.max(axis=0) + p.min(axis=0)) / 2
    longest = max(float(np.ptp(p, axis=0).max()) / 2, 1e-3) * 1.1
    half = np.maximum(np.ptp(p, axis=0) / 2 * 1.1, MIN_BOX_SIDE * longest)
    ax.set_xlim(centre[0] - half[0], centre[0] + half[0])
    ax.set_ylim(centre[1] - half[1], centre[1] + half[1])
    ax.set_zlim(centre[2] - half[2], centre[2] + half[2])
    ax.set_box_aspect(tuple(half / half.max()))


def draw_chain_3d(ax: Any, points: ArrayLike, label: str | None = None, color: str = "#1f5fa8",
                  names: Sequence[str] = (), alpha: float = 1.0) -> None:
    """The arm as a polyline through its joint points (N, 3), base first, joints as dots, optional names."""
    p = np.asarray(points, dtype=float)
    ax.plot(p[:, 0], p[:, 1], p[:, 2], "-", color=color, lw=3, alpha=alpha, label=label, solid_capstyle="round")
    ax.scatter(p[:-1, 0], p[:-1, 1], p[:-1, 2], color="k", s=14, alpha=alpha, depthshade=False)
    ax.scatter(p[-1:, 0], p[-1:, 1], p[-1:, 2], color=color, marker="D", s=24, alpha=alpha, depthshade=False)
    for name, xyz in zip(names, p, strict=False):
        ax.text(*xyz, f" {name}", fontsize=7)
