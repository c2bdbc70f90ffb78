"""Strikes: the contact choice, the window check and the strike planners built on them.

Import the planners from :mod:`optraj.planners`; the modules here hold their pieces:

* ``classic_strike``: :class:`ClassicStrike` (cubic, quintic or LSPB approach, the line, a
  stop); ``time_optimal_strike``: :class:`TimeOptimalStrike` (TOPPRA or Ruckig);
  ``pull_back_strike``: :class:`PullBackStrike`, the pull-back + constant-speed strike of
  the Sawyer pool-cue exercise.
* ``contact``: :func:`choose_contact`, where and in which configuration the ball is met;
  ``contact_choice``: what it returns and the errors it refuses with; ``pool_contact`` and
  ``pool_search``: the pool shot's candidates and their search; ``paddle_contact``: the
  paddle's; ``twist_ratio`` and ``min_max_ratio``: the least share of the velocity limits a
  strike motion needs, and the linear program behind it.
* ``window_check``: :class:`WindowCheck`, whether a strike window fits the limits;
  ``window_nlp``: the small NLP it solves.
"""
