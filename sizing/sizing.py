"""Sizing every joint's drive for a duty cycle and its load cases, the drives' own masses included.

:func:`size_drives` samples the cycle (:func:`armlab.sizing.duty.sample`), computes each joint's load for every
load case (:func:`armlab.sizing.loads.joint_loads`: the arm's inverse dynamics, once per load case for all
candidates) and selects each joint's motor and gearbox (:func:`armlab.sizing.select.select_joint`). The motors'
mass moves the arm: the chosen motors' and gearboxes' masses are put on the links that carry them
(:func:`armlab.sizing.loads.with_link_masses`: joint k+1's drive on link k) and the selection is repeated until it
no longer changes. It stops, not converged, when a selection comes back that was made before (it would cycle)
or after ``max_iterations``; and when a joint has no feasible pair (then nothing is chosen for it).
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from armlab.drives.train import DriveTrain
from armlab.sizing.checks import Conditions
from armlab.sizing.duty import DEFAULT_RATE, CycleSamples, DutyCycle, LoadCase, check_count, sample
from armlab.sizing.loads import Loads, joint_loads, with_link_masses
from armlab.sizing.select import JointSelection, JointTask, check_rank, check_safety_factor, select_joint

if TYPE_CHECKING:
    from armlab.models.arm import Arm
    from armlab.sizing.catalogue import Gearboxes, Motors

__all__ = ["MAX_ITERATIONS", "Sizing", "size"]

#: Selections made at most (the first with the arm alone).
MAX_ITERATIONS = 20


@dataclass(frozen=True)
class Sizing:
    """The result: per joint its :class:`~armlab.sizing.select.JointSelection` of the last iteration; ``arm`` the
    arm carrying the drives chosen before it (what the last selection was made for); ``iterations`` selections
    made, ``converged`` whether the last repeated the one before; the cycle, its samples, the load cases and their
    :class:`~armlab.sizing.loads.Loads` on ``arm``; the catalogues; the safety factor, the ranking and the
    :class:`~armlab.sizing.checks.Conditions`."""

    joints: tuple[JointSelection, ...]
    arm: Arm
    iterations: int
    converged: bool
    cycle: DutyCycle
    samples: CycleSamples
    cases: tuple[LoadCase, ...]
    loads: Loads
    motors: Motors
    gearboxes: Gearboxes
    safety_factor: float
    rank: str
    conditions: Conditions = field(default_factory=Conditions)

    def __repr__(self) -> str:
        if not self.feasible:
            missing = ", ".join(j.joint for j in self.joints if j.chosen is None)
            return f"<Sizing {self.arm.name}: infeasible ({missing} without a feasible motor and gearbox)>"
        return (f"<Sizing {self.arm.name}: {len(self.joints)} joints sized, drive mass {self.drive_mass:.4g} kg, "
                f"smallest margin {self.margin:.3g}, {self.iterations} iteration(s)"
                f"{'' if self.converged else ', not converged'}>")

    def _repr_html_(self) -> str:
        """Jupyter's view: the summary, then one row per joint: the chosen motor and gearbox, ratio, mass (kg) and
        margin, or the joint's nearest infeasible pair and why it fails."""

        rows = []
        for j in self.joints:
            c = j.chosen
            if c is not None:
                rows.append(f"<tr><td>{html.escape(j.joint)}</td><td>{html.escape(c.motor_name)}</td>"
                            f"<td>{html.escape(c.gearbox_name)}</td><td>{c.ratio:.4g}</td><td>{c.mass:.4g}</td>"
                            f"<td>{c.margin:.3g}</td></tr>")
            else:
                why = "; ".join(j.nearest[0].failed) if j.nearest else "no pair checked"
                rows.append(f"<tr><td>{html.escape(j.joint)}</td><td colspan=5>none feasible: "
                            f"{html.escape(why)}</td></tr>")
        return (f"<div><b>{html.escape(repr(self)[1:-1])}</b><table><tr><th>joint</th><th>motor</th><th>gearbox</th>"
                f"<th>ratio</th><th>mass (kg)</th><th>margin</th></tr>{''.join(rows)}</table></div>")

    @property
    def feasible(self) -> bool:
        """Whether every joint has a feasible pair."""
        return all(j.chosen is not None for j in self.joints)

    @property
    def drive_mass(self) -> float:
        """Total mass (kg) of the chosen motors and gearboxes (NaN unless :attr:`feasible`)."""
        return float(sum(j.chosen.mass for j in self.joints if j.chosen is not None)) if self.feasible else np.nan

    @property
    def margin(self) -> float:
        """The smallest margin of the chosen pairs (NaN unless :attr:`feasible`)."""
        return float(min(j.chosen.margin for j in self.joints if j.chosen is not None)) if self.feasible else np.nan

    def drive_train(self) -> DriveTrain:
        """The chosen drives as a :class:`~armlab.drives.train.DriveTrain` (G, J_m + J_g, η; the joints' own
        friction, the arm's drive train's B and T_c, kept); ``ValueError`` unless :attr:`feasible`."""
        chosen = [j.chosen for j in self.joints]
        if any(c is None for c in chosen):
            raise ValueError("no drive train: " + "; ".join(j.joint for j in self.joints if j.chosen is None)
                             + " has no feasible motor and gearbox")
        im = np.array([c.motor for c in chosen if c is not None])
        ig = np.array([c.gearbox for c in chosen if c is not None])
        own = self.arm.drives or DriveTrain.ideal(im.size)
        return DriveTrain(self.gearboxes.ratio[ig], self.motors.rotor_inertia[im] + self.gearboxes.input_inertia[ig],
                          self.gearboxes.efficiency[ig], own.viscous, own.coulomb, own.coulomb_speed,
                          own.coulomb_negative)


def _tasks(arm: Arm, samples: CycleSamples, loads: Loads) -> list[JointTask]:
    return [JointTask.of(samples, loads, k) for k in range(arm.n)]


def size(arm: Arm, cycle: DutyCycle, cases: tuple[LoadCase, ...], motors: Motors, gearboxes: Gearboxes,
         safety_factor: float = 1.0, rank: str = "mass", iterate: bool = True, rate: float = DEFAULT_RATE,
         max_iterations: int = MAX_ITERATIONS, conditions: Conditions | None = None) -> Sizing:
    """Size ``arm``'s drives for ``cycle`` and every load case (see the module docstring); ``iterate``: repeat the
    selection with the chosen drives' masses on the links until it no longer changes; ``conditions``: ambient
    temperature, bus voltage, brake factor and required gearbox life (default :class:`Conditions()`)."""
    conditions = conditions or Conditions()
    arm.require_dynamics("sizing drives")
    safety_factor, rank = check_safety_factor(safety_factor), check_rank(rank)
    if cycle.n != arm.n:
        raise ValueError(f"the duty cycle moves {cycle.n} joints; {arm.name} has {arm.n}")
    if not cases:
        raise ValueError("no load case: give at least one payload (0 kg for none)")
    check_count(len(cases))
    samples = sample(cycle, rate)
    arm.check_q(samples.q)
    seen: list[tuple] = []
    carried = arm
    converged = False
    for iteration in range(1, max_iterations + 1):
        loads = joint_loads(carried, samples, cases)
        joints = tuple(select_joint(name, task, motors, gearboxes, safety_factor, rank, conditions=conditions)
                       for name, task in zip(arm.joint_names, _tasks(arm, samples, loads), strict=True))
        choice = tuple((j.chosen.motor, j.chosen.gearbox) if j.chosen else None for j in joints)
        if None in choice or not iterate:
            break
        if seen and choice == seen[-1]:
            converged = True
            break
        if choice in seen:
            break
        seen.append(choice)
        if iteration == max_iterations:
            break
        masses = np.array([c.mass for j in joints if (c := j.chosen) is not None])
        carried = with_link_masses(arm, masses)
    return Sizing(joints, carried, iteration, converged, cycle, samples, cases, loads, motors, gearboxes,
                  safety_factor, rank, conditions)
