"""Classic profiles: time scalings (cubic, quintic), LSPB, via points, Cartesian lines, sequences.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces:

* ``time_scaling``: :class:`Cubic` and :class:`Quintic`, with their coefficients; ``peaks``:
  exact polynomial peaks (``roots`` finds the roots, ``peak_bounds`` spares most of them);
  ``duration_search``: the shortest duration of a move with moving ends.
* ``lspb``: :class:`LSPB` and :func:`lspb_trajectory`; ``lspb_timing``: its closed forms.
* ``via_points``: :class:`ViaPoints`; ``via_lspb`` and ``via_quintic``: its two profiles;
  ``via_segments``: what they share.
* ``cartesian``: tool paths and straight lines; ``contact_velocity``: a tool point's joint
  velocity (a paddle's at contact).
* ``sequencer``: :class:`PickAndPlacePlanner`.
"""
