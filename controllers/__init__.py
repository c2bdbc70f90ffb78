"""How to follow a trajectory: pseudo-inverse + PID, the OSQP differential-IK QP, simulation.

Controllers arrive with a later release; the package is importable now so that the layout and
the dependency direction are fixed from the start.
"""

__all__: list[str] = []
