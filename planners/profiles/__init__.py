"""Classic profiles: time scalings (cubic, quintic), LSPB, via points, Cartesian lines, sequences.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces.
"""
