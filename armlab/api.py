"""armlab from a Python script: load an arm, move it, simulate it.

The names here are exported from ``armlab`` itself (``import armlab; armlab.load("urm6")``); the
``armlab`` command line is a thin layer over them. An arm's own kinematics and dynamics are methods
of :class:`~armlab.models.arm.Arm` (``fk``, ``jacobian``, ``tool_motion``, ``inverse_dynamics``,
``manipulability``, ``sigma_min``, ``ik``); motions and simulations are functions:
    >>> import armlab
    >>> arm = armlab.load("rr")
    >>> motion = armlab.quintic(arm, [0.0, 0.5], [1.0, 1.0], tf=2.0)
    >>> run = armlab.simulate(arm, motion, payload=0.5)        # doctest: +SKIP
    >>> run.summary["max_abs_torque"], run.violations            # doctest: +SKIP

Angles are radians, lengths metres, times seconds, torques N·m (forces N for prismatic joints)
throughout. Every function raises ``ValueError`` with a one-line message naming a bad value.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from armlab.diagrams.motions import paper_motion as motion_of_paper
from armlab.diagrams.motions import quintic_motion
from armlab.diagrams.motions import read_segments as read
from armlab.diagrams.plant import PlantOptions
from armlab.diagrams.run import Run
from armlab.diagrams.simulate import (
    DEFAULT_ACCURACY,
    DEFAULT_KD,
    DEFAULT_KP,
    DEFAULT_LOG_PERIOD,
    DIVERGENCE_TOLERANCE,
    SimulationOptions,
)
from armlab.diagrams.simulate import simulate as run_diagram
from armlab.kinematics.quintic import ConstantRate, Motion, QuinticSegment, check_duration
from armlab.models import get_arm

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from armlab.models.arm import Arm

__all__ = ["constant_rate", "draw", "load", "paper_motion", "quintic", "read_segments", "simulate", "through"]


def load(name: str | Path, **parameters: float) -> Arm:
    """An arm: a paper arm's name (``armlab list``: rr, rrrr, arm4r, r2t, urm6), a ``.urdf`` or a DH ``.csv`` file.

    ``parameters`` override a paper arm's parameters (e.g. ``load("urm6", theta3=0.5)``; names as in
    ``armlab show ARM``). ``ValueError`` for an unknown arm or parameter, or a malformed file.
    """
    return get_arm(str(name), **parameters)


def quintic(arm: Arm, q0: ArrayLike, qf: ArrayLike, tf: float, label: str = "") -> Motion:
    """A rest-to-rest quintic from ``q0`` to ``qf`` (each ``(n,)``) in ``tf`` s (paper 000, eqs. 3–6).

    Zero velocity and acceleration at both ends; both ends are checked against the joint limits.
    """
    return quintic_motion(arm, q0, qf, tf, label or "rest-to-rest quintic")


def through(arm: Arm, waypoints: ArrayLike, tf: float | Sequence[float]) -> Motion:
    """Rest-to-rest quintics through ``waypoints`` ``(k + 1, n)``: k segments of ``tf`` s each (or one tf each).

    The arm stops at every waypoint, as paper 000's A → B → C → D → A does.
    """
    points = np.asarray(waypoints, dtype=float)
    if points.ndim != 2 or points.shape[0] < 2:
        raise ValueError(f"waypoints have shape {points.shape}; give at least two rows of {arm.n} joint values")
    durations = (list(tf) if isinstance(tf, Iterable) and np.ndim(tf) != 0
                 else np.broadcast_to(np.asarray(tf, dtype=float), (points.shape[0] - 1,)))
    if len(durations) != points.shape[0] - 1:
        raise ValueError(f"tf has {len(durations)} values; {points.shape[0] - 1} segments need one each (or one tf)")
    segments = tuple(QuinticSegment(a, b, check_duration(t), f"{k + 1}")
                     for k, (a, b, t) in enumerate(zip(points[:-1], points[1:], durations, strict=True)))
    motion = Motion(segments, f"rest-to-rest quintics through {points.shape[0]} waypoints")
    motion.check_limits(arm)
    return motion


def constant_rate(arm: Arm, q0: ArrayLike, rate: ArrayLike, tf: float) -> Motion:
    """Constant joint rates: q = q0 + ω t for ``tf`` s (paper 000's RRRR run, Figs. 18–19); ``rate`` in rad/s or m/s."""
    # as ConstantRate reads them (its fields are the arrays it makes of them)
    start, omega = np.asarray(q0, dtype=float), np.asarray(rate, dtype=float)
    motion = Motion((ConstantRate(start, omega, check_duration(tf), "constant-rate"),), "constant joint rates")
    motion.check_limits(arm)
    return motion


def paper_motion(arm: Arm, path: str | None = None, tf: float | None = None) -> Motion:
    """The motion of the arm's paper (what ``armlab simulate ARM`` runs without motion options)."""
    return motion_of_paper(arm, path, tf)


def read_segments(arm: Arm, path: str | Path) -> Motion:
    """The motion in a segments file (JSON; ``armlab simulate --help`` documents the format)."""
    return read(arm, path)


def simulate(
    arm: Arm,
    motion: Motion,
    payload: float = 0.0,
    gravity: str | ArrayLike | None = None,
    mode: str = "controller",
    kp: float | ArrayLike | None = None,
    kd: float | ArrayLike | None = None,
    ki: float | ArrayLike = 0.0,
    log_period: float | None = None,
    accuracy: float | None = None,
    divergence_tolerance: float | None = None,
) -> Run:
    """Simulate ``arm`` following ``motion`` through paper 000's Fig. 6 as a Drake diagram; a :class:`Run`.

    ``payload``: point mass at the tool (kg); ``gravity``: ``None`` (the arm's), ``"off"``, ``"-z"`` …, or
    (gx, gy, gz) m/s²; ``mode``: ``"controller"`` (computed torque, PD gains ``kp`` 1/s², ``kd`` 1/s, ``ki``
    1/s³; defaults 100, 20, 0) or ``"inverse_dynamics"`` (open loop); ``log_period`` (s, default 0.001);
    ``accuracy``: the integrator's target accuracy (default 1e-6); ``divergence_tolerance``: the tracking
    error (rad or m, default 0.01) past which the run counts as diverged. The arm needs mass data. The keywords
    are checked once, as a :class:`~armlab.diagrams.simulate.SimulationOptions` (what the inner layers take).
    """
    options = SimulationOptions(  # None: the option's default
        PlantOptions(gravity=gravity, payload=payload, ideal_drives=True), mode=mode,
        kp=DEFAULT_KP if kp is None else kp, kd=DEFAULT_KD if kd is None else kd, ki=ki,
        log_period=DEFAULT_LOG_PERIOD if log_period is None else log_period,
        accuracy=DEFAULT_ACCURACY if accuracy is None else accuracy,
        divergence_tolerance=DIVERGENCE_TOLERANCE if divergence_tolerance is None else divergence_tolerance)
    return Run(run_diagram(arm, motion, options), options.divergence_tolerance)


def draw(arm: Arm, q: ArrayLike | None = None, path: str | Path | None = None) -> Figure:
    """The arm's kinematic scheme at joint values ``q`` ``(n,)`` (rad, m; default: the pose ``armlab draw`` shows)
    as a matplotlib figure (a notebook shows it); written to ``path`` (``.png``, ``.svg``, ``.pdf``) only if given.
    """
    # lazy: the drawing needs matplotlib, which armlab.load does not
    from armlab.diagrams.draw import default_q, scheme_figure, write_figure

    fig = scheme_figure(arm, default_q(arm) if q is None else q)
    if path is not None:
        write_figure(fig, path)
    return fig
