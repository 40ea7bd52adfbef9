"""Traffic made by a real simulator (SUMO), written in the formats the data adapters read.

SUMO (``eclipse-sumo``, ``sumolib``, ``traci``; the ``sim`` extra) is imported lazily inside the
functions that run it.
"""
