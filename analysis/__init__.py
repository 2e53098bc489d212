"""Workspaces, singular configurations and design studies (sweeps on a Dask cluster).
May import: base, kinematics, drives, models, collision, presentation, planning, controllers, diagrams, sizing.
"""
