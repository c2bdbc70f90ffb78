"""Constrained optimal control: the CasADi NLP, its transcription and its solves.

Import the planner from :mod:`optraj.planners`; the modules here hold its pieces.
"""
