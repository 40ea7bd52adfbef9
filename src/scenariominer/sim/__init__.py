"""Traffic made by a real simulator (SUMO), written in the formats the data adapters read.

SUMO (``eclipse-sumo``, ``sumolib``, ``traci``; the ``sim`` extra) is imported lazily inside the
functions that run it.

Highway: :func:`scenariominer.sim.highway.simulate_highway_set` writes highD-format recordings
with the simulator's ground truth beside them (:mod:`scenariominer.sim.highway_truth`).
"""
