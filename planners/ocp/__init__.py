"""Constrained optimal control: the CasADi NLP, its transcription and its solves.

Import the planner from :mod:`optraj.planners`; the modules here hold its pieces:

* ``optimal_control``: :class:`OptimalControl`, the planner; ``options``: its settings.
* ``formulation``: problems into specs (phases, fixed states, task rows, a first guess);
  ``guesses``: first guesses; ``problem``: the spec and the built NLP's data.
* ``transcription``: the multiple-shooting NLP; ``structure``, ``rows``, ``parameters``:
  its shape, its constraint rows, its named parameters; ``task_rows/``: the problem's task
  constraints as rows and bounds (``strike_line``, ``tool_contact``, ``boundary_state``,
  ``clearance``); ``clearance``: the spheres a pool strike keeps above the cloth and the
  cue tip off the ball (``OptimalControl(clearance=...)``).
* ``building``: grids, solver options and the first point; ``solve``: one solver call,
  warm or cold; ``solution``: reading the solver's point; ``budget``: the wall-time limit.
* ``rounds`` and ``refinement``: solve, verify and refine until the plan holds;
  ``strike_search``: the search over contact configurations; ``failures``: the errors.

(:class:`planners.ocp.optimal_control.OptimalControl` is the planner; the names
:data:`TIGHT_RATIO`, :data:`POSITION_SHRINKS`, :data:`TIME_BUDGET`, :data:`BUDGET_SPENT` are in
:mod:`planners.ocp.options`, :data:`BINDING` in :mod:`planners.ocp.solution`). A problem's
task constraints (``problem.constraints()``: strike line, tool contact, boundary states)
become NLP rows and bounds in :mod:`planners.ocp.task_rows`, one kind per module; the rounds
of solve, verify and refine are in :mod:`planners.ocp.rounds`.

Contact configuration
    A strike's contact configuration is chosen before the NLP is built
    (:func:`planners.strike.contact.choose_contact`): the IK solution whose Jacobian lets the tool
    reach the strike speed with the smallest joint speeds. A strike no configuration can make
    is rejected there, within a second, with the binding joint and the best reachable speed.
    That check covers the velocity limits only. Close to the fastest speed it allows, the
    line can also need accelerations past their limits, and IPOPT finds the NLP locally
    infeasible. Each further contact is then solved from only if its strike window, with
    the approach into it and the stop after it, can keep within the limits
    (:class:`planners.strike.window_check.WindowCheck`). When no window tried can, the plan raises
    an ``InfeasibleError`` naming the window's binding joint and quantity and a slower speed
    (with ``contact_retries=0``, a ``SolverError`` that says so: other contacts may plan);
    otherwise the last ``SolverError``, whose message adds (when every contact tried needs
    more than :data:`TIGHT_RATIO` of a velocity limit) the ratio, the binding joint and the
    fastest speed the velocity limits allow.
    The chosen contact's ratio (the largest fraction of a velocity limit the line needs)
    also bounds the joint velocities and accelerations at the strike nodes
    (:func:`strike_caps`); the bounds come inside the limits when the ratio is below about
    a third, in slow strikes. Without them a minimum-time plan spends a slow strike's long
    window on self-motion of the redundant arm: it ends the approach with the joints still
    moving fast and brakes them inside the window, and that motion carries the cue off its
    line between nodes.

Objectives
    ``"time"`` (sum of the free phase durations), ``"jerk"`` (integral of the squared
    jerk, scaled by the jerk limits), ``"effort"`` (integral of the squared torques, scaled
    by the effort limits), or a mapping of weights, e.g. ``{"time": 1, "jerk": 0.1}``. A
    small ``regularization`` adds the jerk term and, for redundant arms (7 joints or more),
    a posture term that keeps joints near the middle of their ranges (away from the limits;
    singular configurations are avoided by the contact choice), and a grid term: one that
    keeps neighbouring intervals alike, or, for a free move whose first nodes sit on the
    jerk switches of its slowest joint (:func:`planners.ocp.guesses.switch_times`), one
    that keeps each interval near its first length. Without a time term free
    durations would grow without bound, so they are first minimised and then fixed at
    ``stretch`` times the minimum.

Torque limits
    A state the problem fixes (the start at rest, a move's goal state) has the torques of
    its inverse dynamics whatever the motion: one that needs more than an effort limit (a
    start holding the arm against gravity with limits scaled down) is refused before any
    contact search or solve
    (:func:`planners.time_optimal.lower_bound.check_state_torques`), with the
    joint and the factor on the effort limits a plan needs at least. Within the limits but
    past the torque margin, its node's rows keep only the room the state leaves, and rounds
    count its own share of the limit as settled.

    By default (``torque="auto"``) the NLP is first solved without torque rows and the
    torques are evaluated densely (4 points per interval); only when one exceeds 90 % of its
    limit do rows come in and the NLP is solved again, warm started. ``torque=True`` has
    rows from the first solve, ``False`` none (the checker still reports the torques).

    ``torque_rows="linear"`` (the default) writes them as the RNEA's first-order expansion
    about the previous solution (about the initial guess in a first solve), at every node:
    linear rows whose coefficients are NLP parameters, so one compiled NLP serves every
    round and every problem of the same grid, and the Hessian stays as without torques.
    Each further round expands about the last solution, primal and dual values carried
    over, until the dense torques hold; at that fixed point the rows agree with the RNEA to
    first order. ``"rnea"`` writes the symbolic RNEA itself, at the nodes around the hot
    intervals only: exact rows, but each new set of nodes is a new NLP to build (about a
    second) and its second derivatives make every iteration several times dearer.
    From the second expansion on, the rows at both ends of an interval whose dense torque
    still breaks its limit keep that excess more room (so rounds settle where the binding
    nodes would otherwise swap back and forth, and torques that peak between nodes hold);
    with RNEA rows the margin of every row widens when rows everywhere are not enough.

Verification
    Limits on velocity, acceleration and jerk hold between nodes by construction. Positions
    are bounded at the nodes, and by default (``position_rows="auto"``) checked exactly
    between them after a solve (the extremes of each interval's cubic). Where a piece passes
    a limit, the bounds of its two nodes on that side move in by the excess and the same NLP
    is solved again, warm (up to :data:`POSITION_SHRINKS` times); only if that does not
    settle is it solved with the rows that bound positions between nodes too (the Bernstein
    rows of :mod:`planners.ocp.transcription`, a third of all rows: costly when they are
    always there, and a new NLP to build).
    ``position_rows=True`` has the rows from the first solve.
    The strike line is verified between nodes (quarter points of each interval); where the
    cue tip leaves its tolerance the strike phase gets twice the intervals and the NLP is
    solved again. Judge the result with :func:`planners.check`, as for every planner.

Build and solve apart
    :meth:`OptimalControl.build` returns an :class:`OptimalControlProblem` (the CasADi NLP,
    bounds, parameters and initial guess, open for inspection); :meth:`OptimalControl.solve`
    solves it. Compiled NLPs are cached per structure (robot, limits, intervals, objective,
    solver options) in the process, shared by every planner object
    (:data:`planners.ocp.building.COMPILED`), so problems of the same shape reuse one
    solver and a new planner object plans at once with what an earlier one built; a
    pickled planner arrives without its own references to them.
    :func:`planners.ocp.building.forget_compiled` frees the process's NLPs.

Warm starts
    ``plan(problem, warm_start=traj)``: from a previous solution of the same shape, primal
    and dual values (``traj.metadata["warm_start"]``); from any other trajectory with the
    same phase names (TOPPRA, Ruckig, classic profiles), its states at the nodes. A previous
    pool solution's contact configuration (``traj.metadata["contact_configuration"]``) is
    tried first for the new strike, one local IK away, before any contact search; when the
    search chooses a contact on another IK branch (more than
    :data:`planners.strike.contact.BRANCH_SPREAD` away on some joint), the plan starts cold. A
    warm solve that has not converged after :data:`planners.ocp.transcription.WARM_ITERATIONS`
    iterations is solved again from the same primal point with a fresh barrier.

Failures and the time budget
    A failed solve's ``SolverError`` names its most violated row by group, joint and place
    (e.g. "dynamics (the acceleration step) of right_j3 at interval 12 of the strike phase")
    and the joint limits the solver's last point presses (:data:`BINDING` of their bounds or
    more, torques by the inverse dynamics at the nodes): at an infeasible NLP's point those
    are what keeps the rows from being met. The window check counts the effort limits too,
    so a strike whose window needs more torque than they give is refused with the joint and
    the limit scale it needs at that speed. Each ``plan`` and ``solve`` runs within
    ``time_budget`` seconds of wall time (:data:`TIME_BUDGET` by default): the solver's
    iteration callback stops it at the deadline
    (:func:`planners.ocp.transcription.stop_callback`), and the plan raises a ``SolverError``
    with status :data:`BUDGET_SPENT` that no contact retry catches.

Solve statistics
    ``plan`` sums over every solve it made: ``metadata["iterations"]`` and
    ``metadata["nlp_time"]`` [s] over all rounds (``round_iterations`` lists them, and
    ``rounds`` counts them), and ``evaluation_time`` [s], the part of ``nlp_time`` spent
    evaluating the NLP's functions and derivatives (the rest is the solver's own work);
    ``contact_time`` [s] is the wall time of the contact choice (0 for a move);
    ``warm_started`` tells whether the first solve started from a previous solution's
    multipliers, and ``warm_abandoned`` whether the last one was dropped for a cold one
    (whose iterations and times are counted too); ``status``, ``objective`` and
    ``constraint_violation`` are the last solve's.
"""
