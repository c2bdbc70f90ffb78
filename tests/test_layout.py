"""The layout of design.md: dependencies point one way, the base imports nothing of ours."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ORDER = ["robots", "problems", "planners", "controllers", "physics"]
BASE = {"optraj.errors", "optraj.validation"}
OURS = {"optraj", *ORDER}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return {name for name in names if name.split(".")[0] in OURS}


def _allowed(package: str) -> set[str]:
    return set(ORDER[: ORDER.index(package) + 1])


@pytest.mark.parametrize("package", ORDER)
def test_lower_packages_never_import_higher_ones(package):
    allowed = _allowed(package)
    for path in sorted((ROOT / package).rglob("*.py")):
        for name in _imports(path):
            top = name.split(".")[0]
            if top == "optraj":
                assert name in BASE, f"{path.relative_to(ROOT)} imports {name}; only {BASE} allowed"
            else:
                assert top in allowed, f"{path.relative_to(ROOT)} imports {name} (above {package})"


def test_base_modules_import_nothing_but_errors():
    assert _imports(ROOT / "optraj" / "errors.py") == set()
    assert _imports(ROOT / "optraj" / "validation.py") == {"optraj.errors"}
    assert _imports(ROOT / "optraj" / "__init__.py") == {"optraj.errors"}


@pytest.mark.parametrize("package", ["optraj", *ORDER])
def test_packages_declare_all_and_are_typed(package):
    init = ast.parse((ROOT / package / "__init__.py").read_text())
    assert any(
        isinstance(node, (ast.Assign, ast.AnnAssign))
        and "__all__"
        in ast.unparse(node.targets[0] if isinstance(node, ast.Assign) else node.target)
        for node in init.body
    )
    assert (ROOT / package / "py.typed").exists()


def test_test_file_per_module():
    missing = [
        str(path.relative_to(ROOT))
        for package in ["optraj", *ORDER]
        for path in (ROOT / package).glob("*.py")
        if path.name != "__init__.py" and not (ROOT / "tests" / f"test_{path.stem}.py").exists()
    ]
    assert missing == [], f"modules without tests/test_<module>.py: {missing}"


def test_importing_optraj_is_cheap_and_robots_is_headless():
    code = (
        "import sys, optraj; heavy = {'pinocchio', 'casadi', 'numpy'} & set(sys.modules); "
        "assert not heavy, heavy; import robots; "
        "assert 'matplotlib' not in sys.modules, 'robots imports matplotlib'"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
