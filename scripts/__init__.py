"""Programs on top of armlab: the example arms and scripts (installed); the benchmarks (scripts/bench/) are not.
May import: base, kinematics, drives, models, collision, presentation, planning, controllers,
diagrams, sizing, analysis, api, papers, cli.
"""
