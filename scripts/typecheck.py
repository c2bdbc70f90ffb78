"""Type-check the optraj namespace with mypy, as it is installed.

The packages live in top-level folders that ``pyproject.toml`` maps into ``optraj.*``
(``package-dir``); mypy knows no such mapping, so this script lays the namespace out as links
in a temporary folder (``optraj/robots -> robots``, ...) and checks ``-p optraj`` there with
the ``[tool.mypy]`` settings of ``pyproject.toml``.

Usage: ``python scripts/typecheck.py`` (exit status: mypy's).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("robots", "problems", "planners", "controllers", "physics", "sweeps", "viz")


def main() -> int:
    """Lay out the namespace and run mypy on it; returns mypy's exit status."""
    with tempfile.TemporaryDirectory(prefix="optraj-typecheck-") as folder:
        namespace = Path(folder) / "optraj"
        namespace.mkdir()
        for path in (ROOT / "optraj").iterdir():
            if path.suffix in {".py", ".typed"}:
                (namespace / path.name).symlink_to(path)
        for package in PACKAGES:
            (namespace / package).symlink_to(ROOT / package, target_is_directory=True)
        command = [
            sys.executable,
            "-m",
            "mypy",
            "--config-file",
            str(ROOT / "pyproject.toml"),
            "--cache-dir",
            str(ROOT / ".mypy_cache"),
            "-p",
            "optraj",
        ]
        done = subprocess.run(command, cwd=folder, check=False)
        return done.returncode


if __name__ == "__main__":
    sys.exit(main())
