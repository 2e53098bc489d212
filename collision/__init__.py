"""Collisions: the arm's collision geometry and a scene's obstacles, queried through Drake's ``SceneGraph``.
May import: base, kinematics, drives, models.

:mod:`~armlab.collision.scene` reads a scene file (``--scene``); :mod:`~armlab.collision.model` registers the arm
and the scene with the one plant builder and asks ``SceneGraph`` for every pair's signed distance, closest points
and penetration depth; :mod:`~armlab.collision.capsules` computes the same for capsules and spheres against
capsules, spheres, floors and boxes in batches with numpy, in closed form; :mod:`~armlab.collision.clearance`
gives the clearances of a configuration or a motion, by pair.
"""
