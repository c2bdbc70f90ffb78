"""Where the ball goes: MuJoCo strike worlds, a MuJoCo plant, and the strike outcome.

>>> scene = physics.pool_scene(shot.robot, ball=shot.ball)      # Sawyer, cue, table, ball
>>> result = controllers.simulate(shot.robot, traj, controllers.DiffIKQP(shot.robot),
...                               plant=physics.MujocoPlant(scene))
>>> physics.outcome(result, shot).summary()                     # heading and speed errors
>>> physics.outcome(physics.replay(scene, traj), shot)          # the plan alone
>>> physics.plot_ball_paths({"DiffIKQP": [ball]})               # seen from above
"""

from optraj.physics.contact_watch import ContactWatch
from optraj.physics.outcome import HEADING_TOLERANCE, SPEED_TOLERANCE, Outcome, outcome
from optraj.physics.plant import MujocoPlant
from optraj.physics.plot import plot_ball_paths, plot_heading_errors
from optraj.physics.replay import replay, straight_cue
from optraj.physics.scene import StrikeScene, World, paddle_scene, pool_scene, scene_for

__all__ = [
    "HEADING_TOLERANCE",
    "SPEED_TOLERANCE",
    "ContactWatch",
    "MujocoPlant",
    "Outcome",
    "StrikeScene",
    "World",
    "outcome",
    "paddle_scene",
    "plot_ball_paths",
    "plot_heading_errors",
    "pool_scene",
    "replay",
    "scene_for",
    "straight_cue",
]
