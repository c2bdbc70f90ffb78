"""Strikes: the contact choice, the window check and the strike planners built on them.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces.
"""
