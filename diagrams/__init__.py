"""Drake Systems diagrams: paper 000's Fig. 6 for every arm, built, simulated and logged (pictures: presentation).
May import: base, kinematics, drives, models, collision, presentation, planning, controllers.

* :mod:`.build` — the diagram (trajectory source → inverse dynamics controller → plant, loggers);
  :mod:`.servo` — a servo run's loop in it, started consistently, and linearised about a pose;
  :mod:`.tool_point` — the tool point's p, v, a;
* :mod:`.simulate` — running it and summarizing;
* :mod:`.drives` — what a run asks of the drives: limits checked, divergence found, the drive table;
* :mod:`.run` — a run: its log, summary, files and replay.
"""
