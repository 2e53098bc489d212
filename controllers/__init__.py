"""Controllers of paper 000's Fig. 6: computed torque and pure inverse dynamics (:mod:`.inverse_dynamics`); the servo
loop as drive engineers build it: the controller chosen per run with its tuning rule, saturation and anti-windup
(:mod:`.servo`), the sensors of a sampled controller (:mod:`.sensors`), the current loops and motor windings
(:mod:`.electrics`).
May import: base, kinematics, drives, models, collision, presentation, planning.
"""
