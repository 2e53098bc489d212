"""The :class:`Arm`: one serial arm's parameters, geometry, URDF and Drake plant (:mod:`armlab.models.plant`).

An arm is described once, by its paper's parameters, as paper 003's matrix of nominal
geometry plus bodies, limits and named points (see :mod:`armlab.models.write_urdf`). From
that description come both the URDF file (and so the Drake ``MultibodyPlant``) and,
through the arm's ``forward`` function, the paper's own forward kinematics, which the
tests check against Drake.
"""

from __future__ import annotations

import hashlib
import html
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import outside
from armlab.kinematics.batch import as_batch, chain_points
from armlab.kinematics.locating import LocatingTable
from armlab.limits import check_range
from armlab.models.write_urdf import Body, JointLimits, Point, link_inertials, urdf_text

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

    from armlab.drives.train import DriveTrain
    from armlab.kinematics.dh import DHTable
    from armlab.kinematics.ik_closed_form import ClosedForm
    from armlab.models.extras import MotionFn, PaperScheme
    from armlab.models.meshes import Hull, Shape
    from armlab.models.plant import PlantOptions

__all__ = ["MODELS_DIR", "Arm", "Forward", "ForwardFn", "chosen", "from_paper", "parameter_notes"]

MODELS_DIR = Path(__file__).resolve().parent

@dataclass(frozen=True)
class Forward:
    """Forward kinematics of a batch: the tool pose ``(..., 4, 4)`` and named points ``(..., 3)``.

    ``points`` is ordered base → tool.
    """

    tool: NDArray[np.float64]
    points: dict[str, NDArray[np.float64]]


#: The paper's forward kinematics: q of shape (..., n) → :class:`Forward`.
ForwardFn = Callable[[NDArray[np.float64]], Forward]


def from_paper(default: float, where: str) -> Any:
    """A parameter field whose value is printed in the paper (``where`` says where)."""
    return field(default=default, metadata={"source": f"paper: {where}"})


def chosen(default: float, why: str) -> Any:
    """A parameter field the paper leaves out: "chosen, not from the paper", with the reason."""
    return field(default=default, metadata={"source": f"chosen, not from the paper: {why}"})


def parameter_notes(params: Any) -> dict[str, str]:
    """Where each parameter of a parameters dataclass comes from."""
    return {f.name: f.metadata.get("source", "") for f in fields(params)}


@dataclass(frozen=True, repr=False)
class Arm:
    """A serial robot arm: load one, then ask it about poses, motions and forces.

    ``arm = armlab.load("urm6")`` gives a paper arm (``armlab list``), ``armlab.load("my.urdf")`` or
    ``armlab.load("my_dh.csv")`` your own. Then, with joint values ``q`` ``(n,)`` or a batch ``(N, n)`` in rad
    (m for a prismatic joint), checked against the limits:

    * ``arm.fk(q)`` — the tool pose, 4×4 (m); ``arm.jacobian(q)`` — 6×n, rows [v; ω], world frame;
    * ``arm.ik(target, all=True)`` — every joint solution reaching a position or a pose;
    * ``arm.inverse_dynamics(q, qd, qdd)`` — joint torques (N·m, N); ``arm.manipulability(q)``;
    * ``armlab.simulate(arm, armlab.quintic(arm, q0, qf, tf))`` — a :class:`~armlab.diagrams.run.Run` through
      paper 000's Drake diagram, with its replay, plots and summary;
    * ``arm.joints()``, ``arm.links()``, ``arm.limits`` — what the arm is made of; ``arm.urdf()`` its URDF and
      ``arm.make_plant()`` its Drake ``MultibodyPlant``.

    In Jupyter an arm shows a table of its joints, limits and masses. The fields below are the arm's
    description, as the model modules build it (:mod:`armlab.models`); a user reads them, rarely sets them.
    """

    name: str
    paper: str
    parameters: Mapping[str, float]
    notes: Mapping[str, str]
    table: LocatingTable
    bodies: tuple[Body, ...]
    limits: tuple[JointLimits, ...]
    points: tuple[Point, ...]
    tool_name: str
    gravity: tuple[float, float, float]
    forward_fn: ForwardFn | None = None
    urdf_file: Path | None = None  # a committed file, when the parameters are the defaults
    base_link: str = "base_link"
    #: False for a kinematic arm: one whose file gives no mass data (torques cannot be computed).
    has_dynamics: bool = True
    #: The moving links' names, base to tool (a URDF's own); empty: ``link1`` … ``linkN`` (generated URDFs).
    link_names: tuple[str, ...] = ()
    #: The DH table the arm was made from (a user's DH ``.csv``), else ``None``.
    dh: DHTable | None = None
    #: A user's URDF as Drake reads it (meshes as checked ``file://`` URIs, what Drake cannot use left out:
    #: :func:`armlab.models.read_urdf.from_urdf`); ``None``: Drake reads :attr:`urdf_file` or :meth:`urdf`.
    model_text: str | None = None
    #: Why the tool frame is :attr:`tool_name` (``armlab show`` says it).
    tool_source: str = "the tool frame of the arm's model"
    # What only a paper arm has, from its module (:mod:`armlab.models.extras`); a user's arm has none.
    #: Its paper's closed-form inverse kinematics; ``None``: solved numerically (:func:`armlab.kinematics.ik.solve`).
    closed_form: ClosedForm | None = None
    #: Its paper motion, what ``armlab simulate ARM`` runs (:func:`armlab.planning.motions.paper_motion`).
    motion: MotionFn | None = None
    #: Its named multi-segment paths (``--path``; rr: ``"abcd"``).
    paths: Mapping[str, MotionFn] = field(default_factory=dict)
    #: What ``armlab draw`` shows of it beyond the model: the paper figure, the DH table, the default pose.
    scheme: PaperScheme | None = None
    #: The drive train per joint (gear ratio, rotor inertia, efficiency, friction; :mod:`armlab.drives.train`),
    #: from the arm's file (a DH table's drive columns, a URDF's ``<dynamics>`` and ``<transmission>``) or a drive
    #: file (:meth:`with_drives`); ``None``: ideal drives. The plant, the controller's model and
    #: :meth:`inverse_dynamics` all include it.
    drives: DriveTrain | None = None

    def with_drives(self, drives: DriveTrain | None) -> Arm:
        """This arm with the drive train ``drives`` (one per joint) instead of its own; ``None``: ideal drives."""
        if drives is not None and drives.n != self.n:
            raise ValueError(f"{self.name}: the drive train has {drives.n} joint(s); the arm has {self.n} "
                             f"({', '.join(self.joint_names)})")
        return replace(self, drives=drives)
    #: Pairs of links (URDF names) never checked for collision beyond the adjacent ones and those that touch by
    #: construction (:func:`armlab.models.write_urdf.touching_pairs`), each by design (the arm's module says why);
    #: written into its URDF as Drake collision filter groups.
    collision_filters: tuple[tuple[str, str], ...] = ()
    #: A user's URDF's STL and COLLADA collision meshes, as the vertices of their convex hulls: Drake reads neither
    #: kind, so the plant registers them itself (:func:`armlab.models.plant.add_arm_plant`).
    collision_hulls: tuple[Hull, ...] = ()
    #: An SDFormat or MJCF file's collision shapes, on the arm's links (:func:`armlab.models.read_sdf.from_model_file`):
    #: the plant registers them (:func:`armlab.models.plant.add_arm_plant`).
    collision_shapes: tuple[Shape, ...] = ()
    #: A rest pose its source names (rad, m; a library arm's "home" or "ready"), where ``armlab plan ARM to``
    #: starts when no ``--from`` is given; ``None``: none named.
    home: tuple[float, ...] | None = None

    def __repr__(self) -> str:
        kinds = "".join(row.kind for row in self.table.rows)
        mass = f"{sum(body.mass for body in self.bodies):.4g} kg" if self.has_dynamics else "no mass data"
        g = ", ".join(f"{v:g}" for v in self.gravity)
        return f"<Arm {self.name}: {self.n} joints {kinds}, {mass}, tool {self.tool_name}, gravity ({g}) m/s²>"

    def _repr_html_(self) -> str:
        """Jupyter's view: the arm's name and paper, then one row per joint: type, limits (° for revolute
        joints), effort and speed limits, and the mass of the link it moves."""
        masses = [link["mass"] for link in self.links()]

        def value(v: float | None, revolute: bool, unit: str, deg: bool = False) -> str:
            if v is None:
                return "—"
            return f"{np.degrees(v):.4g}°" if (revolute and deg) else f"{v:.4g} {unit}"

        rows = []
        for name, r, lim, mass in zip(self.joint_names, self.revolute, self.limits, masses, strict=True):
            rows.append(
                f"<tr><td>{html.escape(name)}</td><td>{'revolute' if r else 'prismatic'}</td>"
                f"<td>{value(lim.lower, r, 'm', True)}</td><td>{value(lim.upper, r, 'm', True)}</td>"
                f"<td>{value(lim.effort, r, 'N·m' if r else 'N')}</td>"
                f"<td>{value(lim.velocity, r, 'rad/s' if r else 'm/s')}</td><td>{value(mass, r, 'kg')}</td></tr>")
        return (f"<div><b>{html.escape(repr(self)[1:-1])}</b><br>{html.escape(self.paper)}"
                "<table><tr><th>joint</th><th>type</th><th>lower</th><th>upper</th><th>effort limit</th>"
                f"<th>speed limit</th><th>link mass</th></tr>{''.join(rows)}</table></div>")

    def require_dynamics(self, what: str) -> None:
        """``ValueError`` (saying how to add mass data) unless the arm has mass data; ``what`` needs it."""
        if not self.has_dynamics:
            raise ValueError(f"{self.name} is a kinematic arm (its file gives no masses): {what} needs mass data; "
                             "add the mass columns to the DH table (mass,cx,cy,cz,Ixx,…; see the README) "
                             "or <inertial> elements to the URDF")

    # ------------------------------------------------------------------ joints
    @property
    def n(self) -> int:
        """Number of joints (degrees of freedom)."""
        return self.table.n

    @property
    def joint_names(self) -> list[str]:
        """URDF joint names, base to tool."""
        return [row.name for row in self.table.rows]

    @property
    def revolute(self) -> NDArray[np.bool_]:
        """True for each revolute joint."""
        return np.array([row.kind == "R" for row in self.table.rows])

    def joints(self) -> list[dict[str, Any]]:
        """``[{name, type, lower, upper}]`` in SI, ``None`` where a joint is unlimited."""
        return [
            {"name": row.name, "type": "revolute" if row.kind == "R" else "prismatic",
             "lower": lim.lower, "upper": lim.upper}
            for row, lim in zip(self.table.rows, self.limits, strict=True)
        ]

    def limit_arrays(self, unlimited: float = np.inf) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper joint limits (rad or m); a joint without limits gets ``−unlimited``, ``+unlimited``."""
        lower = np.array([-unlimited if lim.lower is None else lim.lower for lim in self.limits])
        upper = np.array([unlimited if lim.upper is None else lim.upper for lim in self.limits])
        return lower, upper

    def check_q(self, q: ArrayLike, name: str = "q", deg: bool = False) -> NDArray[np.float64]:
        """``q`` as an array, raising ``ValueError`` for a wrong count, NaN/inf or a value outside limits
        (:func:`armlab.bounds.outside`: a value round-off beyond a limit is on it).

        An unlimited joint's value is held to ``armlab.limits.LIMITS["q"]`` (±1e6 rad). ``deg``: the user gave
        revolute values in degrees, so the error quotes them in degrees.
        """
        q = as_batch(q, self.n, name)
        for i, (row, lim) in enumerate(zip(self.table.rows, self.limits, strict=True)):
            if lim.lower is None or lim.upper is None:  # an unlimited revolute joint has neither
                continue
            values = q[..., i]
            bad = outside(values, lim.lower, lim.upper)
            if np.any(bad):
                shown = np.array([values[bad].flat[0], lim.lower, lim.upper])
                unit = "m" if row.kind == "T" else ("deg" if deg else "rad")
                value, lower, upper = np.degrees(shown) if unit == "deg" else shown
                raise ValueError(f"{self.name}: {row.name} = {value:.6g} {unit} is outside its limits "
                                 f"[{lower:.6g}, {upper:.6g}] {unit}")
        return check_range(q, name, key="q")  # the unlimited joints

    # -------------------------------------------------------------- dynamics
    def mass_properties(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Each moving link's mass (kg, ``(n,)``), centre of mass (m, ``(n, 3)``) and inertia (kg·m², ``(n, 3, 3)``).

        The inertia is about the centre of mass. Expressed in the link frames {i} of the arm's URDF
        (:attr:`table`'s frames; the frame of joint i's child link), exactly what the Drake plant is
        built from. ``ValueError`` for a kinematic arm.
        """
        self.require_dynamics("the mass properties")
        masses, coms, inertias = self._mass_arrays
        return masses.copy(), coms.copy(), inertias.copy()  # copies: callers may change theirs

    @cached_property
    def _mass_arrays(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """:meth:`mass_properties`, made once per arm (the arm's fields do not change; every batch of inverse
        dynamics asks for them)."""
        masses, coms, inertias = zip(*link_inertials(self.table, self.bodies), strict=True)
        return np.array(masses), np.array(coms), np.array(inertias)

    def links(self) -> list[dict[str, Any]]:
        """``[{name, joint, mass, com, inertia}]`` per moving link, base to tool, in the link frame {i} (SI).

        ``mass`` kg, ``com`` [x, y, z] m, ``inertia`` 3×3 kg·m² about the centre of mass;
        all three ``None`` for a kinematic arm (no mass data).
        """
        names = self.link_names or tuple(f"link{i}" for i in range(1, self.n + 1))
        out = []
        for i, (name, joint) in enumerate(zip(names, self.joint_names, strict=True)):
            entry: dict[str, Any] = {"name": name, "joint": joint, "mass": None, "com": None, "inertia": None}
            if self.has_dynamics:
                mass, com, inertia = link_inertials(self.table, self.bodies)[i]
                entry.update(mass=mass, com=com.tolist(), inertia=inertia.tolist())
            out.append(entry)
        return out

    # ------------------------------------------------------------ kinematics
    def forward(self, q: ArrayLike) -> Forward:
        """The paper's forward kinematics of one configuration or a batch ``(..., n)``.

        Joint limits are not enforced here (workspace
        sweeps go beyond them); use :meth:`check_q` for user input.
        """
        q = as_batch(q, self.n)
        if self.forward_fn is not None:
            return self.forward_fn(q)
        return self.table_forward(q)

    def table_forward(self, q: ArrayLike) -> Forward:
        """Forward kinematics from the matrix of nominal geometry (paper 003, eqs. 8–9)."""
        tool, points = chain_points(as_batch(q, self.n), self.table.steps,
                                    {point.name: (point.link, point.xyz) for point in self.points}, self.table.tool)
        return Forward(tool, points)

    # ------------------------------------------------------------------ URDF
    def urdf(self, drives: DriveTrain | None = None, ros_limits: bool = False, upright: bool = False) -> str:
        """The URDF text of this arm, from the one builder (:func:`armlab.models.write_urdf.urdf_text`), with the
        drive train ``drives`` as Drake's tags (``None``: none); ``ros_limits``: unknown effort and velocity
        limits written as 0, as ROS tools need them; ``upright``: the arm's gravity, where it is not −z (rr's −y),
        written as a ``world`` root link its base is turned in, so that every reader's −z gravity is the arm's."""
        comment = (  # a paper arm's own name; no other (a user's name is the robot's attribute, not a comment)
            f"{self.name}: {self.paper}. Generated by armlab.models from the parameters "
            + ", ".join(f"{k}={v:g}" for k, v in self.parameters.items()) if self.parameters
            else f"{self.paper}. Generated by armlab.models")
        return urdf_text(self.name, self.table, self.bodies, self.limits, self.points, self.tool_name, comment, drives,
                         ros_limits, self.collision_filters, self.gravity if upright else None)

    @property
    def urdf_path(self) -> Path:
        """The arm's URDF file: the committed one (default parameters) or the user's.

        ``ValueError`` for an arm whose URDF is generated (a DH table, overridden parameters): that
        URDF is never written to disk; :meth:`urdf` gives its text, :attr:`urdf_key` names it.
        """
        if self.urdf_file is None:
            raise ValueError(f"{self.name}: its URDF is generated in memory, not a file (arm.urdf() gives the text)")
        return self.urdf_file

    @property
    def urdf_key(self) -> str:
        """A name for the arm's URDF, for caches: the file's path, or ``sha256:…`` of the generated text."""
        if self.urdf_file is not None:
            return str(self.urdf_file)
        return "sha256:" + hashlib.sha256(self.urdf().encode()).hexdigest()

    # ----------------------------------------------------------------- Drake
    def make_plant(self, options: PlantOptions | None = None) -> MultibodyPlant:
        """A finalized ``MultibodyPlant`` of the arm (default: continuous, the arm's gravity, no payload), in the arm's
        joint order: :func:`armlab.models.plant.make_plant`, the one plant builder, with ``options``."""
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.models.plant import make_plant

        return make_plant(self, options)

    # ------------------------------------------------- the Python API (armlab.load(...).fk(q), …)
    def fk(self, q: ArrayLike) -> NDArray[np.float64]:
        """The tool pose in the base (world) frame: ``(4, 4)`` for ``q`` ``(n,)``, ``(N, 4, 4)`` for ``(N, n)``.

        ``q``: joint values (rad, m), checked for count, finite values and the joint limits.
        """
        return self.forward(self.check_q(q)).tool

    def jacobian(self, q: ArrayLike) -> NDArray[np.float64]:
        """Geometric Jacobian of the tool point in the world frame, rows [v; ω]: ``(6, n)`` or ``(N, 6, n)``.

        Column j maps q̇_j (rad/s or m/s) to the tool point's velocity (m/s) and angular velocity (rad/s).
        """
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.differential import jacobian

        return jacobian(self, self.check_q(q))

    def tool_motion(
        self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The tool point's twist [v; ω] (m/s, rad/s) and classical acceleration [a; ω̇] (m/s², rad/s²), world frame.

        Each ``(6,)`` for one state, ``(N, 6)`` for a batch; ``qd``, ``qdd`` shaped like ``q``.
        """
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.differential import tool_motion

        return tool_motion(self, self.check_q(q), *self._rates(qd, qdd))

    def inverse_dynamics(
        self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, gravity: str | ArrayLike | None = None,
        payload: float = 0.0, drives: DriveTrain | None = None,
    ) -> NDArray[np.float64]:
        """Joint-side torques τ = M(q) q̈ + C(q, q̇) q̇ − τ_g(q) + G²·J_m·q̈ + B·q̇ + T_c·tanh(q̇/v_s) (N·m, or N for
        prismatic joints): ``(n,)`` or ``(N, n)``; the last three terms are the drive train's.

        ``gravity``: ``None`` (the arm's), ``"off"``, ``"-z"`` …, or (gx, gy, gz) m/s²; ``payload``: a point mass
        (kg) at the tool point; ``drives``: a :class:`~armlab.drives.train.DriveTrain`, ``None``: the arm's own
        (:attr:`drives`, what its plant applies; ideal if it has none). The motor side of these torques is
        :func:`armlab.drives.train.motor_torque`. The arm needs mass data (``has_dynamics``).
        """
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.rnea import inverse_dynamics

        return inverse_dynamics(self, self.check_q(q), *self._rates(qd, qdd), gravity=gravity, payload=payload,
                                drives=drives)

    def _rates(self, qd: ArrayLike, qdd: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint rates and accelerations checked for shape, finite values and ``armlab.limits`` ranges."""
        return check_range(as_batch(qd, self.n, "qd"), "qd"), check_range(as_batch(qdd, self.n, "qdd"), "qdd")

    def manipulability(
        self, q: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None,
    ) -> NDArray[np.float64] | float:
        """Yoshikawa's manipulability √det(J Jᵀ) of the tool: the product of the singular values of J's rows ``axes``.

        ``axes``: ``"trans"`` (rows v), ``"rot"`` (ω) or ``"all"``; default ``"all"`` for n ≥ 6, else ``"trans"``.
        A float for one ``q``, ``(N,)`` for a batch; 0 at a singular configuration.
        """
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.differential import manipulability

        return manipulability(self.jacobian(q), axes)

    def sigma_min(
        self, q: ArrayLike, axes: Literal["all", "trans", "rot"] | None = None,
    ) -> NDArray[np.float64] | float:
        """The smallest singular value of the tool Jacobian's rows ``axes`` (see :meth:`manipulability`)."""
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.differential import sigma_min

        return sigma_min(self.jacobian(q), axes)

    def ik(
        self, target: ArrayLike, all: bool = False, near: ArrayLike | None = None, pitch: float | None = None,
    ) -> NDArray[np.float64]:
        """Joint values reaching ``target``, within the limits: ``(k, n)``, nearest to ``near`` first.

        ``target``: a tool position ``(3,)`` (rr: ``(2,)``) or a pose ``(4, 4)``. ``all``: every solution (the
        closed-form branches of rr, arm4r, r2t and of a pose of a UR arm or of a spherical wrist: Puma 560, IRB 140,
        KR 5, Stanford; for other arms every distinct solution a multi-start search finds; a continuum — a position
        on more than three joints, a pose on more than six — its solutions at the parameter of the local solution:
        its tool orientation, or its joints 7 … n), else one:
        the nearest branch, or the numerical solver's from ``near`` (default q = 0; one start, a few ms).
        ``pitch``: arm4r's tool pitch θ2+θ3+θ4 (rad).
        ``ValueError`` for an unreachable target (with the closest distance) or one outside the joint limits.
        """
        # lazy: armlab --help loads armlab.models.arm but not this (start-up time)
        from armlab.kinematics.ik import solve

        if not isinstance(all, bool | np.bool_):
            raise TypeError(f"all: expected True or False, got {type(all).__name__}")
        return np.array(solve(self, target, pitch=pitch, near=near, all_solutions=all))
