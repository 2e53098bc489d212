"""Controllers of paper 000's Fig. 6: computed torque and pure inverse dynamics (:mod:`.inverse_dynamics`).
May import: base, kinematics, drives, models, collision, presentation, planning.
"""
