"""Draw a :class:`~optraj.viz.scene.Scene` in MeshCat and export it as one HTML page.

MeshCat (the ``viz`` extra) runs a small server process on the loopback interface; the
scene is sent to it, and ``static_html()`` asks it for a self-contained page: the viewer's
JavaScript and every drawing command, the animation included. :class:`MeshcatViewer` starts
that server and stops it again (use it as a context manager).

Layout of the MeshCat tree: ``/meshcat/optraj/robot/visuals/<geometry>`` for the robot
(Pinocchio's :class:`~pinocchio.visualize.MeshcatVisualizer`), ``/meshcat/optraj/scene/<shape>``
for the rest. The page keeps no camera target, and its camera orbits the origin: the whole
``/meshcat/optraj`` group is shifted so that the scene's target sits at the origin. MeshCat's
own grid (at z = 0) and axes are hidden; the scene brings its floor.
"""

from __future__ import annotations

import contextlib
import io
from types import TracebackType
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.errors import MissingDependencyError, OptrajError
from optraj.viz.scene import Scene
from optraj.viz.shapes import Shape

__all__ = ["ROOT", "MeshcatViewer", "import_meshcat"]

FloatArray = NDArray[np.float64]

#: MeshCat node (under /meshcat) that holds everything optraj draws.
ROOT = "optraj"
#: How often the animation plays when the page opens (then it holds the last frame; the
#: viewer's Animations panel replays it).
REPETITIONS = 1
#: Turns MeshCat's cylinders (along y) onto our z axis.
_Y_TO_Z = np.array(
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


def import_meshcat() -> Any:
    """The ``meshcat`` module.

    Raises:
        MissingDependencyError: meshcat is not installed; names the ``viz`` extra.
    """
    try:
        import meshcat
    except ImportError as exc:
        raise MissingDependencyError("meshcat", "viz", "the 3-D viewer (optraj.viz)") from exc
    return meshcat


class MeshcatViewer:
    """A MeshCat server and client showing one scene at a time.

    >>> with MeshcatViewer() as viewer:
    ...     viewer.show(scene)
    ...     page = viewer.static_html()

    Raises:
        MissingDependencyError: meshcat is not installed.
    """

    def __init__(self) -> None:
        meshcat = import_meshcat()
        with contextlib.redirect_stdout(io.StringIO()):  # it prints its URL
            self._vis = meshcat.Visualizer()
        self._open = True

    @property
    def url(self) -> str:
        """The live viewer's address (loopback), while the server runs."""
        return str(self._vis.url())

    @property
    def running(self) -> bool:
        """Whether the server process is alive."""
        process = getattr(self._vis.window, "server_proc", None)
        return process is not None and process.poll() is None

    def show(self, scene: Scene) -> None:
        """Replace what is drawn by ``scene``: robot, shapes, camera and animation.

        A still scene (one frame) gets no animation.
        """
        self._require_open()
        from meshcat.animation import Animation
        from pinocchio.visualize import MeshcatVisualizer

        vis = self._vis
        vis[ROOT].delete()
        for path in ("/Grid", "/Axes"):
            vis[path].set_property("visible", False)
        robot = MeshcatVisualizer(scene.robot.model, None, scene.geometry)
        robot.initViewer(viewer=vis)
        robot.loadViewerModel(rootNodeName=f"{ROOT}/robot")
        robot.display(scene.q[0])
        for shape in scene.shapes:
            _draw(vis[f"{ROOT}/scene/{shape.name}"], shape)
        shift = np.eye(4)
        shift[:3, 3] = -np.asarray(scene.target)
        vis[ROOT].set_transform(shift)
        x, y, z = (float(v) for v in np.asarray(scene.camera) - np.asarray(scene.target))
        # The camera node is y-up: (x, y, z) of ours is (x, z, -y) there.
        vis["/Cameras/default/rotated/<object>"].set_property("position", [x, z, -y])
        if len(scene.times) > 1:
            animation = Animation(default_framerate=scene.fps)
            _animate_robot(animation, vis, robot, scene)
            _animate_shapes(animation, vis, scene)
            vis.set_animation(animation, play=True, repetitions=REPETITIONS)

    def static_html(self) -> str:
        """The scene as one self-contained HTML page (the viewer's script inlined)."""
        self._require_open()
        return str(self._vis.static_html())

    def close(self) -> None:
        """Stop the server process and close the connection (idempotent)."""
        if not self._open:
            return
        self._open = False
        window = self._vis.window
        window.zmq_socket.close(linger=0)
        process = getattr(window, "server_proc", None)
        if process is not None:
            process.kill()
            process.wait()
            for stream in (process.stdout, process.stderr):
                if stream is not None:
                    stream.close()

    def __enter__(self) -> MeshcatViewer:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()

    def _require_open(self) -> None:
        if not self._open:
            raise OptrajError("this MeshcatViewer is closed; open a new one")


def _draw(node: Any, shape: Shape) -> None:
    import meshcat.geometry as mg
    from pinocchio.visualize.meshcat_visualizer import createCapsule

    r, g, b, a = shape.rgba
    material = mg.MeshPhongMaterial(
        color=int(r * 255) * 65536 + int(g * 255) * 256 + int(b * 255),
        transparent=a < 1.0,
        opacity=float(a),
    )
    if shape.kind == "box":
        geometry = mg.Box(list(shape.size))
    elif shape.kind == "sphere":
        geometry = mg.Sphere(shape.size[0])
    elif shape.kind == "cylinder":
        geometry = mg.Cylinder(shape.size[1], shape.size[0])
    else:
        geometry = createCapsule(shape.size[1], shape.size[0])
    node.set_object(geometry, material)
    node.set_transform(_node_pose(shape, shape.pose))


def _node_pose(shape: Shape, pose: FloatArray) -> FloatArray:
    return np.asarray(pose @ _Y_TO_Z if shape.kind == "cylinder" else pose, dtype=float)


def _animate_robot(animation: Any, vis: Any, robot: Any, scene: Scene) -> None:
    model, data = scene.robot.model, robot.data
    geometry, placements = scene.geometry, robot.visual_data
    names = [
        robot.getViewerNodeName(item, pin.GeometryType.VISUAL) for item in geometry.geometryObjects
    ]
    for k, q in enumerate(scene.q):
        pin.forwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, geometry, placements)
        with animation.at_frame(vis, k) as frame:
            for index, name in enumerate(names):
                frame[name].set_transform(placements.oMg[index].homogeneous)


def _animate_shapes(animation: Any, vis: Any, scene: Scene) -> None:
    for shape in scene.shapes:
        if shape.motion is None:
            continue
        for k, pose in enumerate(shape.motion):
            with animation.at_frame(vis, k) as frame:
                frame[f"{ROOT}/scene/{shape.name}"].set_transform(_node_pose(shape, pose))
