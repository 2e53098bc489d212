"""Workspaces, singular configurations, design studies (sweeps on a Dask cluster) and many planning queries on the
same cluster (:mod:`.plans`).
May import: base, kinematics, drives, models, collision, presentation, planning, controllers, diagrams, sizing.
"""
