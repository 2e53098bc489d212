"""Motions to run: the paper motions, quintics between configurations, segments files, and the fastest timing
within the drives' limits (:mod:`.timing`, Drake's Toppra).
May import: base, kinematics, drives, models, collision, presentation.
"""
