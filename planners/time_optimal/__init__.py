"""Time-optimal profiles: TOPPRA along a path, Ruckig between states, and their lower bound.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces.
"""
