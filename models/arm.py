"""The :class:`Arm`: one serial arm's parameters, geometry, URDF and Drake plant.

An arm is described once, by its paper's parameters, as paper 003's matrix of nominal
geometry plus bodies, limits and named points (see :mod:`armlab.models.urdf`). From
that description come both the URDF file (and so the Drake ``MultibodyPlant``) and,
through the arm's ``forward`` function, the paper's own forward kinematics, which the
tests check against Drake.
"""

from __future__ import annotations

import hashlib
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.kinematics.batch import as_batch
from armlab.kinematics.locating import LocatingTable
from armlab.models.urdf import Body, JointLimits, Point, urdf_text

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

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


@dataclass(frozen=True)
class Arm:
    """A serial arm. Build one with an arm module's ``build()`` or :func:`armlab.models.get_arm`."""

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
        """``q`` as an array, raising ``ValueError`` for a wrong count, NaN/inf or a value outside limits.

        ``deg``: the user gave revolute values in degrees, so the error quotes them in degrees.
        """
        q = as_batch(q, self.n, name)
        for i, (row, lim) in enumerate(zip(self.table.rows, self.limits, strict=True)):
            if lim.lower is None:
                continue
            values = q[..., i]
            bad = (values < lim.lower - 1e-12) | (values > lim.upper + 1e-12)
            if np.any(bad):
                shown = np.array([values[bad].flat[0], lim.lower, lim.upper])
                unit = "m" if row.kind == "T" else ("deg" if deg else "rad")
                value, lower, upper = np.degrees(shown) if unit == "deg" else shown
                raise ValueError(f"{self.name}: {row.name} = {value:.6g} {unit} is outside its limits "
                                 f"[{lower:.6g}, {upper:.6g}] {unit}")
        return q

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
        frames = self.table.frames(q)
        points = {}
        for point in self.points:
            T = frames[..., point.link, :, :]
            points[point.name] = T[..., :3, :3] @ np.asarray(point.xyz) + T[..., :3, 3]
        return Forward(frames[..., -1, :, :], points)

    # ------------------------------------------------------------------ URDF
    def urdf(self) -> str:
        """The URDF text of this arm, from the one builder (:func:`armlab.models.urdf.urdf_text`)."""
        comment = (
            f"{self.name}: {self.paper}. Generated by armlab.models from the parameters "
            + ", ".join(f"{k}={v:g}" for k, v in self.parameters.items())
        )
        return urdf_text(self.name, self.table, self.bodies, self.limits, self.points, self.tool_name, comment)

    @property
    def urdf_path(self) -> Path:
        """Path of the URDF file: the committed one for default parameters, else a generated copy."""
        if self.urdf_file is not None:
            return self.urdf_file
        text = self.urdf()
        digest = hashlib.sha1(text.encode()).hexdigest()[:12]
        path = Path(tempfile.gettempdir()) / "armlab-urdf" / f"{self.name}-{digest}.urdf"
        if not path.exists():
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{digest}.tmp")
            tmp.write_text(text)
            tmp.replace(path)
        return path

    # ----------------------------------------------------------------- Drake
    def add_to_plant(self, plant: MultibodyPlant) -> Any:
        """Parse the URDF into ``plant``, weld its root link to the world (no offset); returns the model instance.

        ``package://NAME/…`` paths resolve through the ``package.xml`` of the URDF's folder or of the two
        above it (a ROS package's layout). A joint without a ``<transmission>`` gets an actuator of its own.
        ``ValueError`` if Drake cannot load the file.
        """
        from pydrake.multibody.parsing import Parser
        from pydrake.multibody.tree import JointActuatorIndex

        parser = Parser(plant)
        parser.SetAutoRenaming(True)
        urdf = self.urdf_path
        for folder in list(urdf.parents)[:3]:
            if (folder / "package.xml").is_file():
                parser.package_map().AddPackageXml(str(folder / "package.xml"))
        try:
            (instance,) = parser.AddModels(file_name=str(urdf))
        except RuntimeError as error:
            raise ValueError(f"{urdf}: Drake cannot load it: {str(error).strip().splitlines()[0]}") from None
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(self.base_link, instance))
        actuators = (plant.get_joint_actuator(JointActuatorIndex(i)) for i in range(plant.num_actuators()))
        actuated = {a.joint().name() for a in actuators if a.model_instance() == instance}
        for name in self.joint_names:
            if name not in actuated:
                plant.AddJointActuator(f"{name}_actuator", plant.GetJointByName(name, instance))
        return instance

    def make_plant(
        self, time_step: float = 0.0, gravity: ArrayLike | None = None
    ) -> MultibodyPlant:
        """A finalized continuous-time (``time_step=0``) ``MultibodyPlant`` of the arm."""
        from pydrake.multibody.plant import MultibodyPlant

        plant = MultibodyPlant(time_step)
        self.add_to_plant(plant)
        plant.mutable_gravity_field().set_gravity_vector(
            np.asarray(self.gravity if gravity is None else gravity, dtype=float)
        )
        plant.Finalize()
        return plant
