import sys

import pytest
from viz_support import object_paths, pool_case

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.viz.export import iframe, notebook_view, scene_html, write_html

pytest.importorskip("meshcat", reason="needs optraj[viz]")


@pytest.mark.slow
def test_write_html_writes_a_self_contained_page(tmp_path):
    shot, traj = pool_case()
    path = write_html(tmp_path / "shot.html", shot.robot, traj, shot, fps=10.0)
    page = path.read_text(encoding="utf-8")
    assert path == tmp_path / "shot.html"
    assert "<!DOCTYPE html>" in page and "MeshCat.Viewer" in page
    assert "http://" not in page.split("<script>")[0]  # nothing fetched from a server
    assert {"/meshcat/optraj/scene/ball", "/meshcat/optraj/scene/table/cloth"} <= object_paths(page)


@pytest.mark.slow
def test_notebook_view_embeds_the_page_in_an_iframe():
    shot, traj = pool_case()
    view = notebook_view(shot.robot, traj, shot, at=0.0, height=300)
    assert view.data.startswith('<div style="width: 100%"><iframe srcdoc=')
    assert "height: 300px" in view.data
    assert "&lt;!DOCTYPE html&gt;" in view.data


def test_iframe_escapes_the_page():
    text = iframe('<p title="a">&</p>', 200.0)
    assert 'srcdoc="&lt;p title=&quot;a&quot;&gt;&amp;&lt;/p&gt;"' in text


def test_bad_path_height_and_missing_meshcat_are_typed_errors(tmp_path, monkeypatch):
    shot, traj = pool_case()
    with pytest.raises(InvalidInputError, match="path must be a str"):
        write_html(3, shot.robot, traj, shot)
    with pytest.raises(InvalidInputError, match="does not exist"):
        write_html(tmp_path / "nowhere" / "shot.html", shot.robot, traj, shot)
    with pytest.raises(InvalidInputError, match="height"):
        notebook_view(shot.robot, traj, shot, height=10)
    monkeypatch.setitem(sys.modules, "meshcat", None)  # as if not installed
    with pytest.raises(MissingDependencyError, match=r"optraj\[viz\]"):
        scene_html(shot.robot, traj, shot)
