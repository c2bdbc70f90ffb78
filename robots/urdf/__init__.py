"""The URDF files of the shipped robots (data only; :func:`optraj.robots.load` reads them)."""

__all__: list[str] = []
