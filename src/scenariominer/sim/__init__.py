"""Traffic made by a real simulator (SUMO), written in the formats the data adapters read.

SUMO (``eclipse-sumo``, ``sumolib``, ``traci``; the ``sim`` extra) is imported lazily inside the
functions that run it.

Highway: :func:`scenariominer.sim.highway.simulate_highway_set` writes highD-format recordings
with the simulator's ground truth beside them (:mod:`scenariominer.sim.highway_truth`).

Urban: :func:`scenariominer.sim.urban.simulate_urban_set` writes braking scenarios at junctions
and on multi-lane roads as Argoverse 2 logs with vector maps and ``labels.csv`` naming the road
user that forced the ego to brake, from the simulator's own state (:mod:`scenariominer.sim.urban_label`).
"""
