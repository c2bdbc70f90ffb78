"""What is to be done: strike, pick-and-place and waypoint problems, and ready-made scenarios.

Problems arrive with the Trajectory/checker release; the package is importable now so that the
layout and the dependency direction are fixed from the start.
"""

__all__: list[str] = []
