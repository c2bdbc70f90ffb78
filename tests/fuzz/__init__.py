"""The fuzz suite: hypothesis strategies for robots, limits, problems, trajectories and
controller settings, and the properties every public entry must keep.

``pytest`` runs the default profile (about 1,000 cases, derandomized); ``make fuzz`` runs the
``fuzz`` profile (100,000 cases with a fixed seed) through ``benchmarks/fuzz.py``, which
writes a report. See :mod:`fuzz.budget` for how the cases are shared.
"""
