import pytest
from viz_support import (
    animated_paths,
    object_paths,
    paddle_case,
    pool_case,
    rolled_outcome,
    youbot_case,
)

from optraj.errors import OptrajError
from optraj.viz.meshcat_viewer import ROOT, MeshcatViewer
from optraj.viz.scene import build_scene

pytest.importorskip("meshcat", reason="needs optraj[viz]")

ROBOT = f"/meshcat/{ROOT}/robot/visuals"
SCENE = f"/meshcat/{ROOT}/scene"


@pytest.fixture(scope="module")
def viewer():
    with MeshcatViewer() as opened:
        yield opened


@pytest.mark.slow
def test_pool_page_holds_robot_table_ball_line_and_the_animation(viewer):
    shot, traj = pool_case()
    outcome = rolled_outcome(shot, contact_time=traj.phase("strike").t_start + 0.1)
    viewer.show(build_scene(shot.robot, traj, shot, outcome, fps=15.0))
    page = viewer.static_html()
    drawn = object_paths(page)
    expected = {f"{ROBOT}/link_2", f"{ROBOT}/tool/cue", f"{ROBOT}/tool/tip"}
    expected |= {f"{SCENE}/table/cloth", f"{SCENE}/ball", f"{SCENE}/strike_line"}
    assert expected <= drawn
    assert any(path.startswith(f"{SCENE}/ball_path/") for path in drawn)
    moved = animated_paths(page)
    assert {f"{ROBOT}/link_2", f"{ROBOT}/tool/cue", f"{SCENE}/ball"} <= moved
    assert f"{SCENE}/table/cloth" not in moved


@pytest.mark.slow
@pytest.mark.parametrize(
    ("case", "expected"),
    [
        (paddle_case, {f"{ROBOT}/tool/blade", f"{SCENE}/ball", f"{SCENE}/shot_heading"}),
        (youbot_case, {f"{ROBOT}/tool/finger_left", f"{SCENE}/block_0", f"{SCENE}/block_1"}),
    ],
)
def test_paddle_and_youbot_pages(viewer, case, expected):
    problem, traj = case()
    viewer.show(build_scene(problem.robot, traj, problem, fps=5.0))
    page = viewer.static_html()
    drawn = object_paths(page)
    assert expected <= drawn
    assert f"{SCENE}/table/cloth" not in drawn  # the previous scene is gone
    assert f"{ROBOT}/link_2" in animated_paths(page)


@pytest.mark.slow
def test_a_still_scene_has_no_animation_and_a_closed_viewer_stops_its_server():
    problem, traj = youbot_case()
    with MeshcatViewer() as viewer:
        assert viewer.running and viewer.url.startswith("http://127.0.0.1:")
        viewer.show(build_scene(problem.robot, traj, problem, at=1.0))
        page = viewer.static_html()
    assert not viewer.running
    assert animated_paths(page) == set()
    assert f"{SCENE}/block_0" in object_paths(page)
    with pytest.raises(OptrajError, match="closed"):
        viewer.static_html()
    viewer.close()  # closing twice is harmless
