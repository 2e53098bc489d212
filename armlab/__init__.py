"""armlab: serial robot arms modelled, checked and simulated with Drake.

The Python API (:mod:`armlab.api`), in one session::

    import armlab
    arm = armlab.load("urm6")                  # a paper arm, a .urdf or a DH .csv file
    T = arm.fk(q)                               # tool pose 4×4 (a batch (N, n) gives (N, 4, 4))
    J = arm.jacobian(q)                         # 6×n, rows [v; ω], world frame
    tau = arm.inverse_dynamics(q, qd, qdd)      # N·m (N for prismatic joints)
    sols = arm.ik(target, all=True)             # every branch, (k, n)
    run = armlab.simulate(arm, armlab.quintic(arm, q0, qf, 2.0))

The rooms, lowest first; a room imports only the rooms below it (tests/test_layers.py holds it): the base modules
(:mod:`armlab.limits`, :mod:`armlab.bounds`, :mod:`armlab.values`, :mod:`armlab.files`, :mod:`armlab.arm_file`:
ranges, the one boundary rule, values, files),
``armlab.kinematics`` (each paper's method), ``armlab.drives`` (drive trains), ``armlab.models`` (the arms, their
URDF files and plants), ``armlab.collision``, ``armlab.presentation`` (plots, drawings, replays),
``armlab.planning`` (motions and their timing), ``armlab.controllers``, ``armlab.diagrams`` (the Systems diagram),
``armlab.sizing``, ``armlab.analysis``, then this API (:mod:`armlab.api`), ``armlab.papers`` (the reproduction),
``armlab.cli`` and ``armlab.scripts`` (examples). Drake is imported only where needed.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from armlab.api import (
        arc,
        constant_rate,
        draw,
        fastest,
        line,
        load,
        paper_motion,
        plan_path,
        quintic,
        read_segments,
        simulate,
        size_drives,
        through,
        trapezoidal,
    )
    from armlab.collision.clearance import clearance
    from armlab.diagrams.run import Run
    from armlab.drives.train import DriveTrain
    from armlab.kinematics.quintic import ConstantRate, Motion, QuinticSegment
    from armlab.models.arm import Arm
    from armlab.models.export import export

__version__ = "0.1.0"

#: The public names and the modules they live in, imported on first use (PEP 562) so that the CLI's
#: start (``armlab --help``) loads none of them.
_EXPORTS = {
    "Arm": "armlab.models.arm",
    "ConstantRate": "armlab.kinematics.quintic",
    "DriveTrain": "armlab.drives.train",
    "Motion": "armlab.kinematics.quintic",
    "QuinticSegment": "armlab.kinematics.quintic",
    "Run": "armlab.diagrams.run",
    "clearance": "armlab.collision.clearance",
    "export": "armlab.models.export",
    **{name: "armlab.api" for name in ("constant_rate", "draw", "load", "paper_motion", "quintic", "read_segments",
                                       "simulate", "size_drives", "through")},
    **{name: "armlab.api" for name in ("arc", "fastest", "line", "trapezoidal")},  # tool paths, profiles, timing
    "plan_path": "armlab.api",  # motions around obstacles
}

__all__ = [  # the names of _EXPORTS, listed for readers and linters
    "Arm",
    "ConstantRate",
    "DriveTrain",
    "Motion",
    "QuinticSegment",
    "Run",
    "__version__",
    "arc",
    "clearance",
    "constant_rate",
    "draw",
    "export",
    "fastest",
    "line",
    "load",
    "paper_motion",
    "plan_path",
    "quintic",
    "read_segments",
    "simulate",
    "size_drives",
    "through",
    "trapezoidal",
]


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'armlab' has no attribute {name!r}")
    value = getattr(import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
