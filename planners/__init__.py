"""How to do it in time: the Trajectory type, time scalings, TOPPRA, Ruckig, optimal control.

Planners arrive with later releases; the package is importable now so that the layout and the
dependency direction are fixed from the start.
"""

__all__: list[str] = []
