"""Pictures of design studies and workspaces (matplotlib, headless, written atomically).

* :func:`write_plots` — a sweep's ``results.csv`` as one figure per objective column, a panel per
  varied parameter (a curve per value of the other parameter when two vary), and a heat map per
  objective column when exactly two parameters vary.
* :func:`workspace_figures` — a workspace's slices (x–y, x–z; manipulability as colour with a colour
  bar), its singular configurations, and the volume's convergence against N and h.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armlab.presentation.figures import new_figure, save_png

if TYPE_CHECKING:
    from armlab.analysis.study import Study
    from armlab.analysis.workspace import Workspace

__all__ = ["manipulability_norm", "workspace_figures", "write_plots"]


def manipulability_norm(w: np.ndarray) -> Any:
    """The colour scale of manipulability ``w`` ``(m,)`` in every workspace picture (slices.png, the point cloud):
    a square root from its least to its greatest value (manipulability crowds near 0 in most workspaces), a
    matplotlib ``PowerNorm`` (its ``inverse`` gives the value of a shade)."""
    import matplotlib.colors

    return matplotlib.colors.PowerNorm(0.5, vmin=float(w.min()), vmax=float(w.max()))


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def _objective_groups(study: Study) -> dict[str, list[str]]:
    """Objective → its columns (one per joint for the per-joint ones)."""
    return {name: [c for c in study.objective_columns if c == name or c.startswith(name + "_")]
            for name in study.evaluate}


def write_plots(study: Study, rows: dict[int, list[str]], out: Path) -> list[str]:
    """The plots of a sweep from its rows (``results.csv`` by candidate); the file names written.

    Per objective: ``OBJECTIVE.png``, a panel per varied parameter (a row per joint for per-joint
    objectives), and with exactly two varied parameters ``OBJECTIVE_map.png``, a heat map per column.
    """
    if not rows:
        return []
    columns, units = study.columns, study.units()
    table = np.array([[float(x) for x in rows[i][: len(columns) - 1]] for i in sorted(rows)])
    params = [v.column for v in study.vary]
    written = []
    for objective, cols in _objective_groups(study).items():
        fig, axes = new_figure(f"{study.arm}: {objective} against {', '.join(params)}", len(cols), len(params),
                               size=(max(4.2 * len(params), 6.0), 1.0 + 2.8 * len(cols)))
        axes = np.reshape(axes, (len(cols), len(params)))
        for r, col in enumerate(cols):
            y = table[:, columns.index(col)]
            for k, name in enumerate(params):
                _curves(axes[r, k], table, columns, params, units, name, y)
                axes[r, k].set_ylabel(_label(col, units[col]))
        written.append(save_png(fig, out / f"{objective}.png"))
        if len(params) == 2:
            written.append(_heat_maps(study, table, objective, cols, params, units, out))
    return written


def _curves(ax: Any, table: np.ndarray, columns: list[str], params: list[str], units: dict[str, str], name: str,
            y: np.ndarray) -> None:
    """``y`` against parameter ``name``: one curve per value of the other parameter when two vary."""
    x = table[:, columns.index(name)]
    if len(params) == 2:
        other = params[1 - params.index(name)]
        z = table[:, columns.index(other)]
        for value in np.unique(z):
            sel = z == value
            order = np.argsort(x[sel])
            ax.plot(x[sel][order], y[sel][order], "o-", ms=3, label=f"{other} = {value:g} {units[other]}")
        ax.legend(fontsize=7)
    elif len(params) == 1:
        order = np.argsort(x)
        ax.plot(x[order], y[order], "o-", ms=3)
    else:
        ax.plot(x, y, "o", ms=3, alpha=0.6)
    ax.set_xlabel(_label(name, units[name]))


def _heat_maps(study: Study, table: np.ndarray, objective: str, cols: Sequence[str], params: Sequence[str],
               units: dict[str, str], out: Path) -> str:
    columns = study.columns
    xs, ys = (np.array(v.values) for v in study.vary)
    fig, axes = new_figure(f"{study.arm}: {objective} over {params[0]} and {params[1]}", 1, len(cols),
                           size=(5.6 * len(cols) + 0.8, 4.6))
    for ax, col in zip(np.ravel(axes), cols, strict=True):
        grid = np.full((ys.size, xs.size), np.nan)
        for row in table:
            i = int(np.flatnonzero(ys == row[columns.index(params[1])])[0])
            j = int(np.flatnonzero(xs == row[columns.index(params[0])])[0])
            grid[i, j] = row[columns.index(col)]
        ax.grid(False)
        image = ax.pcolormesh(_edges(xs), _edges(ys), np.ma.masked_invalid(grid), cmap="viridis", shading="flat")
        fig.colorbar(image, ax=ax, label=_label(col, units[col]))
        if grid.size <= 120:
            for i, y in enumerate(ys):
                for j, x in enumerate(xs):
                    if np.isfinite(grid[i, j]):
                        ax.text(x, y, f"{grid[i, j]:.3g}", ha="center", va="center", fontsize=7,
                                color="k" if image.norm(grid[i, j]) > 0.6 else "w")
        ax.set_xlabel(_label(params[0], units[params[0]]))
        ax.set_ylabel(_label(params[1], units[params[1]]))
    return save_png(fig, out / f"{objective}_map.png")


def _edges(values: np.ndarray) -> np.ndarray:
    """Cell edges around sorted centres (a single value gets a unit-wide cell)."""
    v = np.sort(values.astype(float))
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def _plane_coords(ws: Workspace, points: np.ndarray) -> np.ndarray:
    """Coordinates in the workspace's own plane (or line: then a second, zero coordinate), (M, 2)."""
    coords = (points - ws.origin) @ ws.basis.T
    return np.column_stack([coords, np.zeros(len(coords))]) if ws.dim == 1 else coords


def workspace_figures(ws: Workspace, out: Path) -> list[str]:
    """``slices.png``, ``convergence.png`` and ``singular.png`` of a workspace, and ``collisions.png`` when the
    collision-free volume was measured; the file names written."""
    return [_slices(ws, out / "slices.png"), _convergence(ws, out / "convergence.png"),
            _singular(ws, out / "singular.png"), *([_collisions(ws, out / "collisions.png")] if ws.free is not None
                                                   else [])]


def _collisions(ws: Workspace, path: Path) -> str:
    """Where the raw and the collision-free workspace differ: the kept tool points of collision-free poses and of
    poses that touch (in the arm's plane, else projected on x–y and x–z)."""
    assert ws.free is not None and ws.collision_free_volume is not None
    panels = [None] if ws.dim < 3 else [(0, 1), (0, 2)]
    fig, axes = new_figure(f"{ws.arm}: workspace {ws.measure} {ws.volume:.4g} {ws.volume_unit}, collision-free "
                           f"{ws.collision_free_volume:.4g} {ws.volume_unit} ({ws.collision_free_fraction:.1%} of the "
                           "poses touch nothing)", 1, len(panels), size=(6.4 * len(panels), 5.8))
    for ax, pair in zip(np.ravel([axes]) if len(panels) > 1 else [axes], panels, strict=True):
        if pair is None:
            xy, names = _plane_coords(ws, ws.points), [_axis_name(b) for b in ws.basis] + ["—"] * (2 - ws.dim)
        else:
            xy, names = ws.points[:, list(pair)], ["xyz"[pair[0]], "xyz"[pair[1]]]
        ax.scatter(xy[ws.free, 0], xy[ws.free, 1], s=2, color="#1f5fa8", linewidths=0, label="collision-free pose")
        ax.scatter(xy[~ws.free, 0], xy[~ws.free, 1], s=3, color="#c0392b", linewidths=0,
                   label="pose in collision (itself or an obstacle)")
        ax.set_xlabel(f"{names[0]} [m]")
        ax.set_ylabel(f"{names[1]} [m]")
        ax.set_aspect("equal")
        ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.1), fontsize=7, markerscale=4)
    return save_png(fig, path)


def _slices(ws: Workspace, path: Path) -> str:
    """Tool points coloured by manipulability: the plane of a planar arm, else slabs through the base
    (x–y at the points' median height, x–z at y = 0), the singular configurations' tool points marked."""
    m = len(ws.manipulability) if ws.manipulability is not None else 0
    pts = ws.points[:m] if m else ws.points
    colour = ws.manipulability if m else None
    marks = _singular_points(ws)
    labels = "xyz"
    cuts: list[tuple[tuple[int, int], int] | None]  # per panel: (the slab's two in-plane axes, its normal)
    if ws.dim < 3:
        cuts = [None]  # the arm's own plane
        fig, axes = new_figure(f"{ws.arm}: workspace ({ws.measure} {ws.volume:.4g} {ws.volume_unit}), "
                               "manipulability", size=(6.4, 5.6))
        axes = [axes]
    else:
        cuts = [((0, 1), 2), ((0, 2), 1)]
        fig, axes = new_figure(f"{ws.arm}: workspace slices (volume {ws.volume:.4g} m³), manipulability", 1, 2,
                               size=(11.5, 5.2))
        axes = list(np.ravel(axes))
    slab = 0.05 * ws.reach
    image = None
    if colour is not None:
        norm = manipulability_norm(colour)
    for ax, cut in zip(axes, cuts, strict=True):
        if cut is None:
            xy = _plane_coords(ws, pts)
            sel = np.ones(len(pts), dtype=bool)
            names = [_axis_name(b) for b in ws.basis] + ["—"] * (2 - ws.dim)
            mark_xy = _plane_coords(ws, marks) if len(marks) else marks
        else:
            pair, normal = cut
            centre = float(np.median(pts[:, normal])) if normal == 2 else 0.0
            sel = np.abs(pts[:, normal] - centre) < slab
            xy = pts[:, list(pair)]
            names = [labels[pair[0]], labels[pair[1]]]
            ax.set_title(f"slab |{labels[normal]} − {centre:.3g} m| < {slab:.3g} m", fontsize=9)
            mark_sel = np.abs(marks[:, normal] - centre) < slab if len(marks) else np.zeros(0, dtype=bool)
            mark_xy = marks[mark_sel][:, list(pair)] if len(marks) else marks
        image = ax.scatter(xy[sel, 0], xy[sel, 1], c=None if colour is None else colour[sel], s=2, cmap="viridis",
                           norm=None if colour is None else norm, linewidths=0)
        if len(mark_xy):
            ax.plot(mark_xy[:, 0], mark_xy[:, 1], "x", color="#c0392b", ms=6, label="singular configurations")
            ax.legend(loc="upper right", fontsize=7)
        ax.set_xlabel(f"{names[0]} [m]")
        ax.set_ylabel(f"{names[1]} [m]")
        ax.set_aspect("equal")
    if colour is not None and image is not None:
        fig.colorbar(image, ax=axes, label="Yoshikawa manipulability w = √det(J Jᵀ)", shrink=0.85)
    return save_png(fig, path)


def _axis_name(direction: np.ndarray) -> str:
    k = int(np.argmax(np.abs(direction)))
    return "xyz"[k] if abs(abs(direction[k]) - 1) < 1e-12 else f"({direction[0]:.2f}, {direction[1]:.2f}, " \
                                                                f"{direction[2]:.2f})"


def _singular_points(ws: Workspace) -> np.ndarray:
    """Tool points of the listed singular configurations (for a single joint's loci: of the kept samples
    moved onto them), shape (k, 3)."""
    return np.array(ws.singular.get("_tool_points", np.zeros((0, 3))), dtype=float).reshape(-1, 3)


def _convergence(ws: Workspace, path: Path) -> str:
    c = ws.convergence
    fig, axes = new_figure(f"{ws.arm}: convergence of the workspace {ws.measure}", 1, 2, size=(10.0, 4.0))
    ax1, ax2 = np.ravel(axes)
    measured = np.array([(n, v) for n, v in zip(c["samples"], c["volume_vs_samples"], strict=True) if v is not None])
    ax1.semilogx(measured[:, 0], measured[:, 1], "o-")  # None: too few samples to fill the cells (module docstring)
    ax1.set_xlabel("joint-space samples N")
    ax1.set_ylabel(f"{ws.measure}, 2·V(h) − V(2h), h = {ws.resolution:.3g} m [{ws.volume_unit}]")
    ax2.plot(c["resolution"], c["volume_vs_resolution"], "o-")
    ax2.set_xlabel("voxel edge h [m]")
    ax2.set_ylabel(f"occupied voxels' {ws.measure} V(h), N = {ws.samples:.3g} [{ws.volume_unit}]")
    ax2.axhline(ws.volume, color="#c0392b", ls="--", lw=1, label=f"extrapolated to h → 0: {ws.volume:.5g}")
    ax2.legend(fontsize=8)
    ax2.set_xlim(left=0)
    return save_png(fig, path)


def _singular(ws: Workspace, path: Path) -> str:
    """σ_min against the one joint it depends on, zeros marked; else its distribution over the samples."""
    s = ws.singular
    loci = s.get("loci")
    if loci is not None:
        fig, ax = new_figure(f"{ws.arm}: σ_min(J) against {loci['joint']} (singular where it is 0)", size=(7.0, 4.0))
        scan = np.array(s["_scan"])
        unit = "deg" if loci["unit"] == "rad" else "m"
        scale = 180 / np.pi if unit == "deg" else 1.0
        ax.plot(scan[:, 0] * scale, scan[:, 1], "-")
        values = np.array(loci["values"]) * scale
        ax.plot(values, np.zeros_like(values), "o", color="#c0392b",
                label="singular: " + ", ".join(f"{v:g}" for v in np.round(values, 6) + 0.0) + f" {unit}")
        ax.set_xlabel(f"{loci['joint']} [{unit}]")
        ax.legend(fontsize=8)
    else:
        sigma_min = ws.sigma_min
        if sigma_min is None:
            raise TypeError(f"{ws.arm}: no σ_min to plot (a workspace computed without its Jacobians)")
        fig, ax = new_figure(f"{ws.arm}: σ_min(J) over {len(sigma_min)} sampled configurations "
                             f"({len(s.get('configurations', []))} refined singular ones listed)", size=(7.0, 4.0))
        ax.hist(np.log10(np.maximum(sigma_min, 1e-300)), bins=60)
        ax.set_xlabel("log10 σ_min(J)")
        ax.set_ylabel("configurations")
    ax.set_ylabel("σ_min(J)" if loci is not None else "configurations")
    return save_png(fig, path)
