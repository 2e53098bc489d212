"""Example arms and scripts for your own arm, installed with armlab.

``arm3r.csv`` is a 3-DOF DH table with masses and limits: ``armlab.load("example:arm3r")`` or
``armlab show example:arm3r`` from any folder; ``drives/rr_motors.csv`` a drive file for paper 000's RR arm with
its motors' electrics (illustrative values: ``armlab simulate rr --drives …/drives/rr_motors.csv --electrics``).
The scripts run from a clone of the repository (``python scripts/examples/size_drives.py``) or installed
(``python -m armlab.scripts.examples.size_drives``): ``size_drives`` (peak/RMS torque, speed and power per joint
for a motion), ``reachable`` (is this pose reachable, and by which branches) and ``paper_figures`` (paper 000's
figures for your own arm).
"""
