"""Time-optimal profiles: TOPPRA along a path, Ruckig between states, and their lower bound.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces:

* ``toppra_planner``: :class:`Toppra`, with its pieces ``toppra_path`` (the geometric path),
  ``toppra_path_checks``, ``toppra_problem``, ``toppra_grid``, ``toppra_constraints``,
  ``toppra_classes`` (toppra's classes, imported on the first plan), ``toppra_solve``,
  ``toppra_verify``, ``toppra_time_law`` and ``toppra_failures``.
* ``ruckig_planner``: :class:`Ruckig`, with its pieces ``ruckig_move`` (one move between
  joint states), ``ruckig_validation``, ``ruckig_calculation``, ``ruckig_conversion`` and
  ``ruckig_limits``; ``ruckig_online``: :class:`OnlineRuckig`, one control tick at a time.
* ``lower_bound``: :func:`lower_bound`, the time no planner can beat for a joint move.
* ``phase_plane``: :func:`~.phase_plane.phase_plane`, TOPPRA's (s, s-dot) plane of a plan (its
  plot in ``phase_plane_plot``).
"""
