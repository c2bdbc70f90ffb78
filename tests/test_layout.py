"""The layout of design.md: dependencies point one way, the base imports nothing of ours."""

from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ORDER = ["robots", "problems", "planners", "controllers", "physics", "sweeps", "viz"]
BASE = {"optraj.errors", "optraj.validation"}
OURS = {"optraj", *ORDER}


def _imports(path: Path) -> set[str]:
    """The modules of ours that ``path`` imports, named as folders: ``optraj.planners.x`` is
    ``planners.x``; ``optraj.errors`` stays itself."""
    tree = ast.parse(path.read_text(), filename=str(path))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "optraj":  # from optraj import planners
                names.update(
                    f"optraj.{alias.name}" if alias.name in ORDER else "optraj"
                    for alias in node.names
                )
            else:
                names.add(node.module)
    return {_folder(name) for name in names if name.split(".")[0] in OURS}


def _folder(name: str) -> str:
    parts = name.split(".")
    return (
        ".".join(parts[1:]) if parts[0] == "optraj" and parts[1:2] in [[p] for p in ORDER] else name
    )


@pytest.mark.slow
def test_our_packages_are_imported_under_optraj_only():
    # The generic folder names (robots, planners, ...) are never import names: installed,
    # they would shadow PyPI packages of the same names.
    for folder in ["optraj", *ORDER, "tests", "benchmarks"]:
        for path in sorted((ROOT / folder).rglob("*.py")):
            tree = ast.parse(path.read_text(), filename=str(path))
            for node in ast.walk(tree):
                tops = []
                if isinstance(node, ast.Import):
                    tops = [alias.name.split(".")[0] for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                    tops = [node.module.split(".")[0]]
                bare = [top for top in tops if top in ORDER]
                assert not bare, f"{path.relative_to(ROOT)} imports {bare} outside optraj"


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


def test_every_package_folder_is_installed():
    # pyproject lists the packages one by one: a sub-package missing there is left out of the
    # wheel, though an editable install still finds it.
    listed = set(
        tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    )
    found = {"optraj"} | {
        ".".join(("optraj", *init.parent.relative_to(ROOT).parts))
        for folder in ORDER
        for init in (ROOT / folder).rglob("__init__.py")
    }
    assert listed == found


#: The test folder of each package folder whose name it does not share: a tests/optraj folder
#: would be imported in place of the optraj package (tests/ is on the path).
TEST_FOLDERS = {"optraj": "top"}


def _test_folder(folder: Path) -> Path:
    """The tests/ sub-folder mirroring the package folder ``folder`` (relative to ROOT)."""
    return Path(TEST_FOLDERS.get(folder.parts[0], folder.parts[0]), *folder.parts[1:])


def _package_folder(folder: Path) -> Path:
    """The package folder (relative to ROOT) that the tests/ sub-folder ``folder`` mirrors."""
    packages = {test: package for package, test in TEST_FOLDERS.items()}
    if not folder.parts:
        return folder
    return Path(packages.get(folder.parts[0], folder.parts[0]), *folder.parts[1:])


def test_test_file_per_module():
    # The tests mirror the packages: planners/ocp/transcription.py is tested by
    # tests/planners/ocp/test_transcription.py, and optraj/cli.py by tests/top/test_cli.py.
    missing = [
        str(path.relative_to(ROOT))
        for package in ["optraj", *ORDER]
        for path in (ROOT / package).rglob("*.py")
        if path.name != "__init__.py"
        and not (
            ROOT / "tests" / _test_folder(path.parent.relative_to(ROOT)) / f"test_{path.name}"
        ).exists()
    ]
    assert missing == [], f"modules without a mirrored tests/.../test_<module>.py: {missing}"


def test_every_test_file_mirrors_a_module_or_is_a_whole_project_test():
    whole_project = {"test_benchmarks.py", "test_layout.py", "test_notebooks.py", "test_readme.py"}
    orphans = []
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        folder = path.parent.relative_to(ROOT / "tests")
        if folder.parts[:1] == ("fuzz",) or (folder == Path(".") and path.name in whole_project):
            continue
        if not (ROOT / _package_folder(folder) / path.name.removeprefix("test_")).exists():
            orphans.append(str(path.relative_to(ROOT)))
    assert orphans == [], f"test files that mirror no module: {orphans}"


def test_importing_optraj_is_cheap_and_robots_is_headless():
    code = (
        "import sys, optraj; heavy = {'pinocchio', 'casadi', 'numpy'} & set(sys.modules); "
        "assert not heavy, heavy; from optraj import robots; "
        "assert 'matplotlib' not in sys.modules, 'robots imports matplotlib'"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_no_module_imports_private_names_of_another():
    # A private name is a module's own: shared code is public (and documented) or moves.
    for folder in ["optraj", *ORDER]:
        for path in sorted((ROOT / folder).rglob("*.py")):
            tree = ast.parse(path.read_text(), filename=str(path))
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("optraj"):
                    private = [a.name for a in node.names if a.name.startswith("_")]
                    assert not private, f"{path.relative_to(ROOT)} imports {private}"


MODULE_LINES = 600  # physical lines per module
CLASS_LINES = 400  # physical lines per class
FUNCTION_LINES = 80  # lines of code per function: no docstring, blank or comment-only lines


def _code_lines(node: ast.AST, source: list[str]) -> int:
    docstring = set()
    body = getattr(node, "body", [])
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        docstring = set(range(body[0].lineno, body[0].end_lineno + 1))
    return sum(
        1
        for number in range(node.lineno, node.end_lineno + 1)
        if number not in docstring and source[number - 1].strip()[:1] not in ("", "#")
    )


def _oversized(path: Path) -> list[str]:
    text = path.read_text()
    source = text.splitlines()
    found = []
    if len(source) > MODULE_LINES:
        found.append(f"module of {len(source)} lines > {MODULE_LINES}")
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ClassDef):
            length = node.end_lineno - node.lineno + 1
            if length > CLASS_LINES:
                found.append(f"class {node.name} of {length} lines > {CLASS_LINES}")
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = _code_lines(node, source)
            if length > FUNCTION_LINES:
                found.append(f"function {node.name} of {length} code lines > {FUNCTION_LINES}")
    return found


@pytest.mark.parametrize(
    "module",
    [
        str(path.relative_to(ROOT))
        for folder in ["optraj", *ORDER]
        for path in sorted((ROOT / folder).rglob("*.py"))
    ],
)
def test_modules_classes_and_functions_stay_small(module):
    assert _oversized(ROOT / module) == []
