"""The papers' reproduction (``armlab reproduce``): one script per paper, their errata, the report and what goes
beyond the papers.
May import: base, kinematics, drives, models, collision, presentation, planning, controllers,
diagrams, sizing, analysis, api.
"""
