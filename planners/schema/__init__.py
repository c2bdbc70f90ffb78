"""The JSON schemas of optraj's file formats (data only; :mod:`..trajectory_schema` reads them)."""

__all__: list[str] = []
