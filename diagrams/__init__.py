"""Drake Systems diagrams: paper 000's Fig. 6 for every arm, and the 3-D views.

* :mod:`.build` — the diagram (trajectory source → inverse dynamics controller → plant, loggers);
* :mod:`.plant` — the one plant builder (:class:`~.plant.PlantOptions`: gravity, payload, drives, geometry);
  :mod:`.tool_point` — the tool point's p, v, a;
* :mod:`.motions` — the paper motions, quintics between configurations, segment files;
* :mod:`.simulate` — running it and summarizing; :mod:`.output`, :mod:`.plots`, :mod:`.graphviz` — files;
* :mod:`.commands` — ``armlab simulate`` and ``armlab diagram``;
* :mod:`.replay`, :mod:`.view` — the animation replay and ``armlab view``.
"""
