"""Motions to run: the paper motions, quintics between configurations, segments files, the fastest timing
within the drives' limits (:mod:`.timing`, Drake's Toppra), and motions planned around obstacles (:mod:`.planner`).
May import: base, kinematics, drives, models, collision, presentation.
"""
