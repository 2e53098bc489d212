"""``armlab draw ARM``: the arm's kinematic scheme, drawn from its model like the papers' figures.

The papers open with each arm's kinematic scheme (000 Figs. 1, 11–13, 20; 001 Figs. 1–2; 003
Figs. 1–2; 004 Figs. 1–3). :func:`draw_arm` draws it for any arm, paper or user's, at joint
values q, from the same model every other command uses:

* the links as a polyline through the frames' origins, the base as a grey block;
* each joint's axis: a revolute joint as a cylinder with an arrow along its axis, a prismatic
  joint as a slider box along its axis;
* the frames {0} … {n} and the tool frame as RGB triads (x red, y green, z blue) with their labels
  (frames at one point share one label);
* the parameters: a DH arm's table (a, α, d, θ; standard or modified, as its model has it) with the
  non-zero lengths written on the links, or a locating-table arm's rows (P_i, k_i, paper 003) with
  P_i written on the links; and the direction of gravity.

The DH frames are DH's own ({i} after row i), computed by :class:`~armlab.kinematics.dh.DHTable`;
the locating frames are :meth:`~armlab.kinematics.locating.LocatingTable.frames`. Both end where
the arm's tool frame is (checked: ``ValueError`` otherwise). The view: a planar arm (every joint
axis parallel, every origin in one plane) is seen face-on along its axes; any other arm from the
front-right, above. Axes are to scale (equal).
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.files import suffix_format, write_file
from armlab.kinematics.dh import DHRow, DHTable

if TYPE_CHECKING:
    from armlab.kinematics.dh import DHTable
    from armlab.models.arm import Arm

__all__ = ["FORMATS", "Scheme", "default_q", "draw_arm", "scheme", "scheme_figure", "write_figure"]

#: Picture formats by file suffix.
FORMATS = ("png", "svg", "pdf")
_AXIS_COLORS = ("#d62728", "#2ca02c", "#1f5fa8")  # x, y, z
_LINK = "#4d5656"


@dataclass
class Scheme:
    """What the scheme shows, in the world frame at one q.

    ``frames``: (label, 4×4 pose) per drawn frame; ``joints``: (point, unit axis, "R"/"T") per
    joint — a point on a revolute joint's axis, the moving end of a prismatic joint's slide;
    ``chain``: (M, 3) polyline of the links; ``link_labels``: (text, midpoint of the link it names);
    ``table_title``, ``table``: the parameter table's title and rows, as text.
    """

    frames: list[tuple[str, NDArray[np.float64]]]
    joints: list[tuple[NDArray[np.float64], NDArray[np.float64], str]]
    chain: NDArray[np.float64]
    link_labels: list[tuple[str, NDArray[np.float64]]]
    table_title: str
    table: list[str]


def _dh_table(arm: Arm) -> DHTable | None:
    """The arm's DH table, if it has one: a paper arm's own (``arm.scheme.dh``) or a user's DH table.

    A user's DH arm keeps its rows as parameters a1, alpha1, d1, theta1, …; the convention is the
    one (standard or modified) whose chain ends at the arm's tool frame.
    """
    if arm.scheme is not None:
        return arm.scheme.dh
    keys = [f"{key}{i + 1}" for i in range(arm.n) for key in ("a", "alpha", "d", "theta")]
    if set(arm.parameters) != set(keys):
        return None
    p = arm.parameters
    rows = tuple(DHRow(p[f"a{i}"], p[f"alpha{i}"], p[f"d{i}"], p[f"theta{i}"], row.kind)
                 for i, row in enumerate(arm.table.rows, start=1))
    q = np.random.default_rng(0).uniform(-1.0, 1.0, size=(4, arm.n))
    for convention in ("standard", "modified"):
        table = DHTable(rows, convention)
        if np.allclose(table.end_pose(q), arm.table.frames(q)[:, -1], atol=1e-9):
            return table
    return None


def _rotation(R: NDArray) -> str:
    """A constant rotation R_i as ", R: <angle>° about (axis)"; nothing for the identity."""
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0))
    if angle < 1e-12:
        return ""
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if np.linalg.norm(axis) < 1e-9:  # a half turn: the axis is R + I's largest column
        axis = (R + np.eye(3))[:, int(np.argmax(np.diag(R)))]
    axis = axis / np.linalg.norm(axis)
    return f", R: {_angle(angle)} about ({', '.join(_fmt(v + 0.0) for v in np.round(axis, 4))})"


def _fmt(x: float) -> str:
    return f"{x:.4g}"


def _angle(x: float) -> str:
    return f"{np.degrees(x):.4g}°"


def scheme(arm: Arm, q: ArrayLike) -> Scheme:
    """The frames, joint axes, links and parameters of ``arm`` at ``q`` (n,) in the world frame."""
    q = arm.check_q(q, "q")
    tool = arm.fk(q)
    table = _dh_table(arm)
    if table is not None:
        frames = table.frames(q)  # DH frames {0} … {n}
        if table.convention == "standard":  # joint i turns about / slides along z_{i−1} (a slide ends at d_i + q_i)
            joints = [(frames[i, :3, 3] + (0.0 if row.kind == "R" else row.d + q[i]) * frames[i, :3, 2],
                       frames[i, :3, 2], row.kind) for i, row in enumerate(table.rows)]
        else:  # modified: about / along z_i
            joints = [(frames[i + 1, :3, 3], frames[i + 1, :3, 2], row.kind) for i, row in enumerate(table.rows)]
        chain = frames[:, :3, 3]
        labels = [f"{{{i}}}" for i in range(arm.n + 1)]
        sub = (lambda i: i - 1) if table.convention == "modified" else (lambda i: i)
        link_labels = []
        for i, row in enumerate(table.rows, start=1):
            lengths = [f"{name}{k} = {_fmt(v)}" for name, v, k in (("d", row.d, i), ("a", row.a, sub(i)))
                       if v != 0 and k >= 0]
            if lengths:
                link_labels.append((", ".join(lengths), (chain[i - 1] + chain[i]) / 2))
        a, alpha = ("a_{i-1}", "α_{i-1}") if table.convention == "modified" else ("a_i", "α_i")
        title = f"{table.convention} DH\ni: {a}, {alpha}, d_i, θ_i"
        rows = [f"{i + 1}: {_fmt(r.a)} m, {_angle(r.alpha)}, "
                + (f"q{i + 1}" + (f" + {_fmt(r.d)}" if r.d else "") if r.kind == "T" else f"{_fmt(r.d)} m")
                + ", " + (f"q{i + 1}" + (f" + {_angle(r.theta)}" if r.theta else "") if r.kind == "R"
                          else _angle(r.theta))
                for i, r in enumerate(table.rows)]
    else:
        frames = arm.table.frames(q)[:-1]  # {0} base, {i} link i (the tool below)
        joints = [(frames[i + 1, :3, 3], frames[i + 1, :3, :3] @ np.asarray(row.k, dtype=float), row.kind)
                  for i, row in enumerate(arm.table.rows)]
        chain = np.concatenate([frames[:, :3, 3], tool[None, :3, 3]])
        labels = [f"{{{i}}}" for i in range(arm.n + 1)]
        link_labels = [(f"P{i + 1}", (chain[i] + chain[i + 1]) / 2) for i in range(arm.n)
                       if np.linalg.norm(chain[i + 1] - chain[i]) > 1e-9]
        title = "locating table (paper 003)\ni: kind, P_i [m], k_i (, R_i)"
        rows = [f"{i + 1}: {r.kind}, ({', '.join(_fmt(v) for v in r.P)}), ({', '.join(_fmt(v) for v in r.k)})"
                + _rotation(np.asarray(r.R, dtype=float)) for i, r in enumerate(arm.table.rows)]
        rows.append(f"tool: ({', '.join(_fmt(v) for v in arm.table.tool[:3, 3])})")
    drawn = list(zip(labels, frames, strict=True))
    if not np.allclose(chain[-1], tool[:3, 3], atol=1e-9):
        raise ValueError(f"{arm.name}: the drawn chain ends at {chain[-1]}, not at the tool {tool[:3, 3]}")
    if np.allclose(frames[-1], tool, atol=1e-9):
        drawn[-1] = (f"{drawn[-1][0]} = tool {arm.tool_name}", frames[-1])
    else:
        drawn.append((f"tool {arm.tool_name}", tool))
    return Scheme(drawn, [(np.asarray(o), np.asarray(k) / np.linalg.norm(k), kind) for o, k, kind in joints],
                  np.asarray(chain), link_labels, title, rows)


def _basis(axis: NDArray) -> tuple[NDArray, NDArray]:
    """Two unit vectors perpendicular to ``axis`` and to each other."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)


def _cylinder(ax: Any, origin: NDArray, axis: NDArray, radius: float, length: float, color: str) -> None:
    u, v = _basis(axis)
    phi = np.linspace(0, 2 * np.pi, 24)
    s = np.array([-length / 2, length / 2])
    ring = radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)  # (24, 3)
    pts = origin + ring[None, :, :] + s[:, None, None] * axis  # (2, 24, 3)
    ax.plot_surface(pts[..., 0], pts[..., 1], pts[..., 2], color=color, alpha=0.55, linewidth=0, shade=True)


def _box(ax: Any, origin: NDArray, axis: NDArray, half_width: float, length: float, color: str) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    u, v = _basis(axis)
    corners = np.array([origin + a * length / 2 * axis + b * half_width * u + c * half_width * v
                        for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)])
    faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]
    ax.add_collection3d(Poly3DCollection([corners[f] for f in faces], facecolor=color, edgecolor="k",
                                         linewidths=0.4, alpha=0.45))


def _view(s: Scheme) -> tuple[float, float]:
    """(elevation, azimuth) in degrees: face-on along the common axis of a planar arm, else front-right above."""
    axes = np.array([k for _, k, _ in s.joints])
    normal = axes[0]
    points = np.concatenate([s.chain, [T[:3, 3] for _, T in s.frames]])
    planar = (np.all(np.abs(np.abs(axes @ normal) - 1) < 1e-9)
              and np.all(np.abs((points - points[0]) @ normal) < 1e-9))
    if not planar:
        return 22.0, -58.0
    normal = normal if normal[np.argmax(np.abs(normal))] > 0 else -normal
    elevation = np.degrees(np.arcsin(np.clip(normal[2], -1, 1)))
    azimuth = np.degrees(np.arctan2(normal[1], normal[0])) if abs(normal[2]) < 1 - 1e-9 else -90.0
    return float(elevation), float(azimuth)


def _frame_labels(fig: Any, ax: Any, labels: list[tuple[str, NDArray]]) -> None:
    """The frames' labels beside their origins, each moved down a line while it would overlap one placed
    before it (on the final layout: the figure is drawn once first)."""
    from mpl_toolkits.mplot3d import proj3d

    fig.canvas.draw()  # fixes the layout, so that data → pixel is final
    line = 9 * fig.dpi / 72 * 1.35  # pixels per line of the 9 pt labels
    char = 9 * fig.dpi / 72 * 0.62
    placed: list[tuple[float, float, float]] = []  # left, bottom, width in pixels
    for text, origin in sorted(labels, key=lambda item: -item[1][2]):  # top down
        x, y, _ = proj3d.proj_transform(*origin, ax.get_proj())
        px, py = ax.transData.transform((x, y))
        left, width, shift = px + 6, char * len(text), 0.0
        while any(left < ql + qw and ql < left + width and abs(py + 4 - shift - qb) < line for ql, qb, qw in placed):
            shift += line
        placed.append((left, py + 4 - shift, width))
        ax.annotate(text, xy=(x, y), xytext=(6, 4 - shift * 72 / fig.dpi), textcoords="offset points", fontsize=9,
                    fontweight="bold", color="k", zorder=6,
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})


def draw_arm(arm: Arm, q: ArrayLike, path: str | Path) -> Path:
    """Draw the kinematic scheme of ``arm`` at joint values ``q`` (n,), SI, into ``path`` (:func:`scheme_figure`).

    The format follows the suffix (``.png``, ``.svg``, ``.pdf``); the file is written completely or
    not at all. ``ValueError`` for a bad suffix or q (count, limits).
    """
    # lazy: armlab --help loads armlab.presentation.draw but not this (start-up time)
    import matplotlib.pyplot as plt

    suffix_format(path, FORMATS)  # before drawing
    fig = scheme_figure(arm, q)
    try:
        return write_figure(fig, path)
    finally:
        plt.close(fig)


def write_figure(fig: Any, path: str | Path) -> Path:
    """``fig`` saved to ``path`` in the format of its suffix (:data:`FORMATS`), completely or not at all."""
    # lazy: armlab --help loads armlab.presentation.draw but not this (start-up time)
    from armlab.presentation.figures import DPI

    fmt = suffix_format(path, FORMATS)
    buffer = io.BytesIO()
    fig.savefig(buffer, format=fmt, dpi=DPI)
    return write_file(path, buffer.getvalue())


def scheme_figure(arm: Arm, q: ArrayLike) -> Any:
    """The kinematic scheme of ``arm`` at joint values ``q`` (n,), SI, as a matplotlib figure (the caller closes
    it): the links, joints and frames in 3-D to scale, and beside them the legend and the arm's DH table.
    ``ValueError`` for a bad q (count, limits)."""
    # lazy: armlab --help loads armlab.presentation.draw but not this (start-up time)
    from armlab.presentation.figures import new_figure, set_equal_3d

    q = arm.check_q(q, "q")
    s = scheme(arm, q)
    qtext = ", ".join(f"{np.degrees(v):.4g}°" if r else f"{v:.4g} m" for v, r in zip(q, arm.revolute, strict=True))
    figure = arm.scheme.figure if arm.scheme is not None else None
    title = f"{arm.name}: kinematic scheme at q = ({qtext})" + (f" — cf. paper {figure}" if figure else "")
    fig, axes = new_figure(title, ncols=2, size=(10.5, 6.5), projection="3d", width_ratios=(3.0, 1.2))
    ax, panel = axes[0]
    panel.remove()
    panel = fig.add_subplot(panel.get_subplotspec())
    panel.set_axis_off()

    points = np.concatenate([s.chain, [T[:3, 3] for _, T in s.frames]])
    size = max(float(np.ptp(points, axis=0).max()), 1e-3)
    triad, radius = 0.12 * size, 0.03 * size

    # Drawn in layers (bodies, links, frames, labels) rather than depth-sorted, so that no body hides a label.
    ax.computed_zorder = False
    ax.plot(*s.chain.T, "-", color=_LINK, lw=4, solid_capstyle="round", label="links", zorder=2)
    ax.scatter(*s.chain[-1], color=_LINK, marker="D", s=30, depthshade=False, zorder=2)
    _box(ax, s.frames[0][1][:3, 3] - np.array([0, 0, radius]), np.array([0.0, 0.0, 1.0]), 1.6 * radius,
         2 * radius, "#aab7b8")  # the base
    for (point, axis, kind), value in zip(s.joints, q, strict=True):
        if kind == "R":
            _cylinder(ax, point, axis, radius, 2.5 * radius, "#f0b27a")
            ax.quiver(*point, *(axis * 1.6 * triad), color="k", lw=1.0, arrow_length_ratio=0.15, alpha=0.6, zorder=3)
        else:  # the slide's box spans the stroke travelled, q_i, back from its moving end
            length = max(abs(value), 0.06 * size)
            _box(ax, point - axis * value / 2, axis, radius, length, "#85c1e9")
    groups: dict[tuple, list[str]] = {}
    for label, T in s.frames:
        for j in range(3):
            ax.quiver(*T[:3, 3], *(T[:3, j] * triad), color=_AXIS_COLORS[j], lw=1.6, arrow_length_ratio=0.2,
                      zorder=3)
        groups.setdefault(tuple(np.round(T[:3, 3], 9)), []).append(label)
    for text, where in s.link_labels:
        ax.text(*where, text, fontsize=7, color="#7b241c", ha="right", va="top", zorder=4,
                bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.7})
    lo, hi = points.min(axis=0), points.max(axis=0)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    set_equal_3d(ax, np.vstack([points, lo - 0.05 * size, hi + 0.08 * size]))
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # a short side of the box gets fewer ticks, not crowded ones
        axis.set_major_locator(MaxNLocator(max(2, round(5 * np.ptp(axis.get_view_interval()) / size))))
    elevation, azimuth = _view(s)
    ax.view_init(elev=elevation, azim=azimuth)
    g = np.asarray(arm.gravity, dtype=float)
    if np.linalg.norm(g) > 0:  # an arrow in a corner of the view box, clear of the arm
        from mpl_toolkits.mplot3d import proj3d

        g = g / np.linalg.norm(g)
        box = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])  # (3, 2): low, high
        centre = box.mean(axis=1)
        arrow = 0.25 * float(np.ptp(box, axis=1).min())  # inside the box's shortest side
        # Up-stream of g along it; across it, the corner whose arrow is farthest from the arm on the screen.
        corners = np.array([[box[i, (k >> i) & 1] for i in range(3)] for k in range(8)])
        corners = corners[np.all((np.abs(g) < 0.5) | (np.sign(corners - centre) == -np.sign(g)), axis=1)]
        starts = corners + 0.15 * (centre - corners)
        drawn = np.concatenate([points, [T[:3, 3] + T[:3, j] * triad for _, T in s.frames for j in range(3)]])
        screen = np.array(proj3d.proj_transform(*drawn.T, ax.get_proj()))[:2].T
        middles = np.array(proj3d.proj_transform(*(starts + g * arrow / 2).T, ax.get_proj()))[:2].T
        start = starts[np.argmax([np.min(np.linalg.norm(screen - m, axis=1)) for m in middles])]
        ax.quiver(*start, *(g * arrow), color="#8e44ad", lw=1.6, arrow_length_ratio=0.25, zorder=3)
        ax.text(*(start + g * arrow), "  g", color="#8e44ad", fontsize=10, zorder=5)  # at the head
    if abs(abs(elevation) - 90) < 1e-6:  # face-on along z: z is the depth, not an axis one can read
        ax.set_zticks([])
        ax.set_zlabel("")
    g_text = ("gravity: " + ", ".join(f"{v:+.3g}" for v in arm.gravity) + " m/s²") if np.any(arm.gravity) else ""
    legend = ["frames: x red, y green, z blue", "revolute joint: cylinder", "  + arrow along its axis",
              "prismatic joint: slider box", g_text, "", *s.table_title.splitlines(), *s.table]
    panel.text(0.0, 0.98, "\n".join(legend), fontsize=8, family="monospace", va="top", ha="left",
               transform=panel.transAxes)
    _frame_labels(fig, ax, [(", ".join(labels), np.array(origin)) for origin, labels in groups.items()])
    return fig


def default_q(arm: Arm) -> NDArray[np.float64]:
    """The pose drawn without ``--q``: a paper arm's own (``arm.scheme.q``: its paper motion's start, e.g. rr
    at (−38°, 98°), paper 000 Fig. 3), any other arm's zeros moved into its limits."""
    if arm.scheme is not None:
        return arm.scheme.q(arm)
    return np.clip(np.zeros(arm.n), *arm.limit_arrays())
