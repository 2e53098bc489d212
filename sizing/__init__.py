"""Choosing drives: motor and gearbox catalogues, duty cycles and load cases, the selection and its mass
iteration, the sizing report.
May import: base, kinematics, drives, models, collision, presentation, planning, controllers, diagrams.
"""
