"""The arm as a continuous-time Drake ``MultibodyPlant``, with gravity and an optional payload.

Paper 000 simulates its RR arm in MSC Adams in a vertical plane with gravity and a basket at the
tool (Fig. 26); paper 003's R2T robot carries a payload of about 20 kg. Here the payload is a point
mass welded to the arm's tool frame (its centre of mass at the tool point), added before
``Finalize`` so the plant and the controller's copy of it are the same model.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

    from armlab.models.arm import Arm

__all__ = ["GRAVITY_NAMES", "G", "check_payload", "make_plant", "resolve_gravity"]

#: Standard gravity (m/s²), the magnitude of every arm's default gravity.
G = 9.81

#: Named gravity settings: "off", and a direction of magnitude G along a base axis.
GRAVITY_NAMES = ("default", "off", "+x", "-x", "+y", "-y", "+z", "-z")


def resolve_gravity(arm: Arm, gravity: str | ArrayLike | None = None) -> NDArray[np.float64]:
    """The gravity vector (m/s², base frame) for ``gravity``.

    ``None`` or ``"default"`` → the arm's default (rr: −y, the vertical plane of paper 000's Adams
    model; the others: −z); ``"off"`` → zero; ``"+x"`` … ``"-z"`` → 9.81 m/s² along that base axis;
    or three numbers (a sequence, or text ``"gx,gy,gz"``).
    """
    if gravity is None:
        return np.asarray(arm.gravity, dtype=float)
    if isinstance(gravity, str):
        text = gravity.strip().lower()
        if text == "default":
            return np.asarray(arm.gravity, dtype=float)
        if text == "off":
            return np.zeros(3)
        if text in GRAVITY_NAMES:
            g = np.zeros(3)
            g["xyz".index(text[1])] = G if text[0] == "+" else -G
            return g
        from armlab.values import parse_floats

        try:
            values = parse_floats(gravity, "--gravity")
        except ValueError as error:
            raise ValueError(f"{error}; or one of {', '.join(GRAVITY_NAMES)}") from None
        gravity = values
    import math

    from armlab.limits import check_range

    g = np.asarray(gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise ValueError(f"gravity {np.ravel(g).tolist()} is not allowed: give 3 finite numbers gx,gy,gz (m/s²) "
                         f"or one of {', '.join(GRAVITY_NAMES)}")
    return check_range(g, "gravity", math.hypot(*g))


def check_payload(payload: float, name: str = "payload") -> float:
    """``payload`` (kg) as a float; ``ValueError`` (naming it ``name``) unless it is a mass in
    :data:`armlab.limits.LIMITS`' range."""
    from armlab.limits import allowed, check_range

    try:
        value = float(payload)
    except (TypeError, ValueError):
        raise ValueError(f"{name} {payload!r} is not allowed: a payload is a mass, {allowed('payload')}") from None
    return float(check_range(value, name))


def make_plant(arm: Arm, gravity: ArrayLike, payload: float = 0.0) -> MultibodyPlant:
    """A finalized continuous-time plant of ``arm`` with ``gravity`` and a ``payload`` point mass (kg) at the tool.

    The plant's generalized positions, velocities and actuators must be in the arm's joint order
    (joint1 … jointN), which the URDF guarantees; this is checked so that a trajectory in the
    arm's joint order can be wired to the plant's ports directly. The mass matrix must be positive
    definite (at q = 0), or the simulation could not solve for the accelerations.

    The drives are ideal: Drake would clamp each actuator's input at the URDF's effort limit (for
    joints with a ``<transmission>`` only); here none is clamped, so a run shows the torque its motion
    takes, and passing a limit is reported (:func:`armlab.diagrams.drives.limit_violations`), never
    silently turned into a lagging arm.
    """
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import JointActuatorIndex, RotationalInertia, SpatialInertia

    arm.require_dynamics("simulate")
    payload = check_payload(payload)
    plant = MultibodyPlant(0.0)
    instance = arm.add_to_plant(plant)
    if payload > 0:
        body = plant.AddRigidBody(
            "payload", instance, SpatialInertia.MakeFromCentralInertia(payload, np.zeros(3), RotationalInertia(0, 0, 0))
        )
        plant.WeldFrames(plant.GetFrameByName(arm.tool_name, instance), body.body_frame())
    plant.mutable_gravity_field().set_gravity_vector(np.asarray(gravity, dtype=float))
    for index in range(plant.num_actuators()):  # the plant holds the arm alone
        plant.get_mutable_joint_actuator(JointActuatorIndex(index)).set_effort_limit(np.inf)
    plant.Finalize()
    order = [plant.GetJointByName(name, instance) for name in arm.joint_names]
    if [j.position_start() for j in order] != list(range(arm.n)) or [j.velocity_start() for j in order] != list(
        range(arm.n)
    ):
        raise ValueError(f"{arm.name}: the plant's joint order differs from {', '.join(arm.joint_names)}")
    if plant.num_actuators() != arm.n or not np.array_equal(plant.MakeActuationMatrix(), np.eye(arm.n)):
        raise ValueError(f"{arm.name}: every joint needs one actuator, in joint order ({', '.join(arm.joint_names)}): "
                         "declare the URDF's <transmission> elements in that order, or none")
    mass_matrix = plant.CalcMassMatrix(plant.CreateDefaultContext())
    if np.any(np.linalg.eigvalsh(mass_matrix) <= 1e-12 * max(1.0, np.abs(mass_matrix).max())):
        still = [name for name, m in zip(arm.joint_names, np.diag(mass_matrix), strict=True) if m <= 1e-12]
        raise ValueError(f"{arm.name}: the mass matrix is singular (joint(s) {', '.join(still) or 'together'} move "
                         "no mass or inertia): to simulate, every moving link needs an <inertial> with mass > 0 and "
                         "inertia")
    return plant
