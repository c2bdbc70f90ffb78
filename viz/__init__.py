"""A 3-D viewer: the robot with its tool, the task's objects and the ball's path, animated.

MeshCat through Pinocchio's visualiser (the ``viz`` extra: ``pip install "optraj[viz]"``);
the output is one self-contained HTML page.

>>> from optraj import viz
>>> viz.write_html("shot.html", shot.robot, traj, problem=shot, outcome=ball)
>>> viz.notebook_view(shot.robot, traj, problem=shot, outcome=ball)   # in Jupyter
>>> scene = viz.build_scene(shot.robot, traj, problem=shot)          # the scene as data
"""

from optraj.viz.export import notebook_view, scene_html, write_html
from optraj.viz.meshcat_viewer import MeshcatViewer
from optraj.viz.robot_geometry import robot_geometry
from optraj.viz.scene import Scene, build_scene
from optraj.viz.shapes import Shape

__all__ = [
    "MeshcatViewer",
    "Scene",
    "Shape",
    "build_scene",
    "notebook_view",
    "robot_geometry",
    "scene_html",
    "write_html",
]
