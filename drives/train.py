"""A drive train per joint: gear ratio, rotor inertia, gearbox efficiency, viscous and Coulomb friction.

Every quantity is given on the **joint side** (the gearbox output), where the arm's torques live, except
the rotor inertia, which is the motor's own (motor side, as datasheets and the Robotics Toolbox give it):

* ``gear_ratio`` G — motor speed = G·q̇ (G ≥ 1 for a reduction; G ≠ 0, its sign is the motor's direction);
* ``rotor_inertia`` J_m (kg·m², motor side) — reflected to the joint as G²·J_m (Drake's
  ``JointActuator`` rotor inertia and gear ratio, which put it on the mass matrix's diagonal);
* ``efficiency`` η in (0, 1] — of the gearbox, both ways;
* ``viscous`` B (N·m·s/rad, joint side) — friction B·q̇ (a URDF's ``<dynamics damping>``);
* ``coulomb`` T_c+ and ``coulomb_negative`` T_c− (N·m, joint side, both ≥ 0; T_c− = T_c+ unless given) —
  friction T_c±·tanh(q̇/v_s), T_c+ while the joint turns forwards (q̇ ≥ 0) and T_c− backwards, smooth so it can
  be simulated (continuous through q̇ = 0, where it is 0), with the speed ``coulomb_speed`` v_s (rad/s, the same
  for every joint; :data:`COULOMB_SPEED` by default). Which one applies goes by the sign of the *joint*
  velocity, as in the Robotics Toolbox (``Link.friction``), whatever the sign of G.

The Robotics Toolbox gives B and T_c on the **motor side** (Corke & Armstrong-Hélouvry 1994 for the Puma
560, T_c as a pair [T_c+, T_c−] with T_c− negative): :meth:`DriveTrain.from_motor_side` converts them once,
B = G²·B_m, T_c± = |G|·|T_c±,m|.

The motor-side torque of a joint-side torque τ (which includes the reflected inertia and friction) is
:func:`motor_torque`: τ/(G·η) when the drive delivers power (τ·q̇ ≥ 0) and τ·η/G when the load drives it
back (τ·q̇ < 0: the gearbox's losses then help the motor). Prismatic joints read N for N·m, m for rad.

A drive train may carry its motors' electrics (``electrics``, :class:`~armlab.drives.motor.MotorElectrics`: R, L,
k_t, k_e, bus voltage, peak current), which a simulation with ``electrics=True`` runs through a current loop, and
its gearboxes' elasticity (``elasticity``, :class:`~armlab.drives.elastic.Elasticity`), which one with
``elastic=True`` simulates as a two-mass joint.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import below

if TYPE_CHECKING:
    from armlab.drives.elastic import Elasticity
    from armlab.drives.motor import MotorElectrics

__all__ = ["COULOMB_SPEED", "DRIVE_FIELDS", "DriveTrain", "joint_vector", "motor_speed", "motor_torque"]

#: v_s (rad/s or m/s) of the smooth Coulomb friction T_c·tanh(q̇/v_s): 99.5 % of T_c at 3·v_s = 0.03 rad/s.
COULOMB_SPEED = 0.01

#: The per-joint fields of a :class:`DriveTrain` (:meth:`DriveTrain.fields`: those a symmetric train needs).
DRIVE_FIELDS = ("gear_ratio", "rotor_inertia", "efficiency", "viscous", "coulomb", "coulomb_negative")

#: The fields, their units and what is allowed, for messages.
_ALLOWED = {
    "gear_ratio": ("", "a finite number other than 0"),
    "rotor_inertia": ("kg·m²", "a finite number ≥ 0"),
    "efficiency": ("", "a number in (0, 1]"),
    "viscous": ("N·m·s/rad", "a finite number ≥ 0"),
    "coulomb": ("N·m", "a finite number ≥ 0"),
    "coulomb_negative": ("N·m", "a finite number ≥ 0 (the magnitude |T_c−|: the toolbox's Tc[1] is negative)"),
}


def joint_vector(value: ArrayLike, label: str, n: int | None, unit: str, allowed_text: str,
                 bad: Callable[[NDArray[np.float64]], NDArray[np.bool_]]) -> NDArray[np.float64]:
    """``value`` as one number per joint ``(n,)`` (``n`` ``None``: any count); ``ValueError`` naming ``label`` (``"drive
    train gear_ratio"``), the joint, the value with its ``unit`` and what is allowed, where ``bad`` of the array is
    true, or for a value that is no vector of numbers."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{label} = {value!r} is not allowed: {allowed_text} per joint") from None
    if a.ndim != 1 or (n is not None and a.size != n):
        raise ValueError(f"{label} has shape {a.shape}; expected one value per joint" + (f" ({n})" if n is not None
                                                                                           else ""))
    wrong = bad(a)
    if wrong.any():
        k = int(np.argmax(wrong))
        raise ValueError(f"{label} of joint {k + 1} = {a[k]:g}{' ' + unit if unit else ''} is not allowed: "
                         f"{allowed_text}")
    return a


def _bad(name: str, a: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Where a drive-train field's values are not allowed (:data:`_ALLOWED`)."""
    if name == "gear_ratio":
        return ~np.isfinite(a) | (a == 0)
    if name == "efficiency":
        return ~np.isfinite(a) | (a <= 0) | (a > 1)
    return ~np.isfinite(a) | (a < 0)


def _vector(value: ArrayLike, name: str, n: int | None) -> NDArray[np.float64]:
    unit, allowed_text = _ALLOWED[name]
    return joint_vector(value, f"drive train {name}", n, unit, allowed_text, lambda a: _bad(name, a))


@dataclass(frozen=True)
class DriveTrain:
    """Per-joint drive-train parameters, each shape ``(n,)``, joint side except J_m (see the module);
    ``coulomb`` is T_c+ and ``coulomb_negative`` T_c− (``None``: T_c+, a symmetric friction, which follows
    ``coulomb`` through :func:`dataclasses.replace`); ``electrics``: the motors' (``None``: not known);
    ``elasticity``: the gearboxes' stiffness and damping (``None``: rigid)."""

    gear_ratio: NDArray[np.float64]
    rotor_inertia: NDArray[np.float64]
    efficiency: NDArray[np.float64]
    viscous: NDArray[np.float64]
    coulomb: NDArray[np.float64]
    coulomb_speed: float = COULOMB_SPEED
    coulomb_negative: NDArray[np.float64] | None = None
    electrics: MotorElectrics | None = None
    elasticity: Elasticity | None = None

    def __post_init__(self) -> None:
        n = None
        for f in fields(self):
            if f.name not in DRIVE_FIELDS or (f.name == "coulomb_negative" and self.coulomb_negative is None):
                continue
            a = _vector(getattr(self, f.name), f.name, n)
            n = a.size
            object.__setattr__(self, f.name, a)
        v_s = float(self.coulomb_speed)
        if not (np.isfinite(v_s) and v_s > 0):
            raise ValueError(f"drive train coulomb_speed = {self.coulomb_speed!r} rad/s is not allowed: "
                             "a positive finite speed")
        object.__setattr__(self, "coulomb_speed", v_s)
        for name in ("electrics", "elasticity"):
            part = getattr(self, name)
            if part is not None and part.n != n:
                raise ValueError(f"drive train {name} have {part.n} joint(s); the drive train has {n}")

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.gear_ratio.size)

    @classmethod
    def ideal(cls, n: int) -> DriveTrain:
        """Direct drives: G = 1, no rotor inertia, η = 1, no friction."""
        return cls(np.ones(n), np.zeros(n), np.ones(n), np.zeros(n), np.zeros(n))

    @classmethod
    def from_motor_side(cls, gear_ratio: ArrayLike, rotor_inertia: ArrayLike, efficiency: ArrayLike,
                        viscous_motor: ArrayLike, coulomb_motor: ArrayLike, coulomb_speed: float = COULOMB_SPEED,
                        coulomb_negative_motor: ArrayLike | None = None) -> DriveTrain:
        """From motor-side friction as the Robotics Toolbox gives it: B = G²·B_m, T_c± = |G|·T_c±,m (``coulomb_motor``
        T_c+,m and ``coulomb_negative_motor`` |T_c−,m|, ≥ 0; ``None``: symmetric)."""
        g = _vector(gear_ratio, "gear_ratio", None)
        b_m = _vector(viscous_motor, "viscous", g.size)
        tc_m = _vector(coulomb_motor, "coulomb", g.size)
        negative = None if coulomb_negative_motor is None else np.abs(g) * _vector(coulomb_negative_motor,
                                                                                   "coulomb_negative", g.size)
        return cls(g, np.asarray(rotor_inertia, dtype=float), np.asarray(efficiency, dtype=float),
                   g**2 * b_m, np.abs(g) * tc_m, coulomb_speed, negative)

    @property
    def has_coulomb(self) -> bool:
        """Whether any joint has Coulomb friction (T_c± > 0): a diagram then applies and compensates it."""
        return bool(np.any(self.coulomb > 0) or np.any(self.negative > 0))

    @property
    def negative(self) -> NDArray[np.float64]:
        """T_c− per joint ``(n,)`` (N·m, joint side, ≥ 0): ``coulomb_negative``, or T_c+ for a symmetric train."""
        return self.coulomb if self.coulomb_negative is None else self.coulomb_negative

    @property
    def asymmetric(self) -> bool:
        """Whether some joint's Coulomb friction differs by direction (T_c− ≠ T_c+)."""
        return bool(np.any(self.negative != self.coulomb))  # exact: data as given, not a computed value

    @property
    def coulomb_max(self) -> NDArray[np.float64]:
        """max(T_c+, T_c−) per joint ``(n,)`` (N·m): the most Coulomb friction can take, either way."""
        return np.maximum(self.coulomb, self.negative)

    def per_joint(self, name: str) -> NDArray[np.float64]:
        """The field ``name`` of :data:`DRIVE_FIELDS` ``(n,)`` (``coulomb_negative``: T_c−, :attr:`negative`)."""
        return self.negative if name == "coulomb_negative" else getattr(self, name)

    def fields(self) -> tuple[str, ...]:
        """The per-joint fields this train needs written: :data:`DRIVE_FIELDS`, without ``coulomb_negative`` for a
        symmetric friction."""
        return DRIVE_FIELDS if self.asymmetric else DRIVE_FIELDS[:-1]

    @property
    def reflected_inertia(self) -> NDArray[np.float64]:
        """G²·J_m per joint (kg·m², joint side), shape ``(n,)``."""
        return self.gear_ratio**2 * self.rotor_inertia

    def coulomb_friction(self, qd: ArrayLike) -> NDArray[np.float64]:
        """Joint-side Coulomb friction torque T_c±·tanh(q̇/v_s) (N·m; T_c+ for q̇ ≥ 0, T_c− below) for rates
        ``(..., n)``, same shape."""
        qd = np.asarray(qd, dtype=float)
        level = np.where(qd >= 0, self.coulomb, self.negative) if self.asymmetric else self.coulomb
        return level * np.tanh(qd / self.coulomb_speed)

    def friction(self, qd: ArrayLike) -> NDArray[np.float64]:
        """Joint-side friction torque B·q̇ + T_c±·tanh(q̇/v_s) (N·m) for rates ``(..., n)``, same shape."""
        return self.viscous * np.asarray(qd, dtype=float) + self.coulomb_friction(qd)

    def torque(self, qd: ArrayLike, qdd: ArrayLike) -> NDArray[np.float64]:
        """What the drive train adds to the arm's joint torques: G²·J_m·q̈ + friction(q̇), shape ``(..., n)``."""
        return self.reflected_inertia * np.asarray(qdd, dtype=float) + self.friction(qd)


def motor_torque(train: DriveTrain, tau: ArrayLike, qd: ArrayLike) -> NDArray[np.float64]:
    """Motor-side torque (N·m) of joint-side torques ``tau`` at rates ``qd``, both ``(..., n)``.

    τ/(G·η) where the drive delivers power (τ·q̇ ≥ 0), τ·η/G where it is driven back (τ·q̇ < 0; a power of zero
    within the slack, :func:`armlab.bounds.below`, is delivered: at rest, round-off in q̇ does not decide).
    """
    tau = np.asarray(tau, dtype=float)
    delivering = ~below(tau * np.asarray(qd, dtype=float), 0.0)
    return np.where(delivering, tau / (train.gear_ratio * train.efficiency),
                    tau * train.efficiency / train.gear_ratio)


def motor_speed(train: DriveTrain, qd: ArrayLike) -> NDArray[np.float64]:
    """Motor speed G·q̇ (rad/s), shape of ``qd`` ``(..., n)``."""
    return train.gear_ratio * np.asarray(qd, dtype=float)
