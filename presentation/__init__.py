"""Pictures of arms and runs: the figures' style, a run's plots, drawings of arms, graphviz files, the 3-D replay
and the live viewer.
May import: base, kinematics, drives, models, collision.
"""
