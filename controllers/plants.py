"""Every plant a controller can be simulated on, in one place.

:class:`Plant` and :class:`PlantState` are in :mod:`controllers.plant`, the concrete plants
in :mod:`controllers.kinematic_plant` and :mod:`controllers.dynamic_plant`; MuJoCo's is
:class:`physics.MujocoPlant`. Import them from here or from :mod:`optraj.controllers`.
"""

from optraj.controllers.dynamic_plant import DynamicPlant
from optraj.controllers.kinematic_plant import KinematicPlant
from optraj.controllers.plant import (
    Plant,
    PlantState,
    frozen_state,
    impulse_response,
    tool_force_to_joint_velocity,
)

__all__ = [
    "DynamicPlant",
    "KinematicPlant",
    "Plant",
    "PlantState",
    "frozen_state",
    "impulse_response",
    "tool_force_to_joint_velocity",
]
