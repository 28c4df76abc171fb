"""Fixtures of the installation and package tests: those of the Python suite (a DDS domain of
the test's own, processes that are always reaped), and the build tree under test."""

import importlib.util
import os
from pathlib import Path

_spec = importlib.util.spec_from_file_location(
    "macsim_python_fixtures", Path(__file__).resolve().parents[1] / "python" / "conftest.py")
_fixtures = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_fixtures)

domain = _fixtures.domain
spawn = _fixtures.spawn
SOURCE_DIR = _fixtures.SOURCE_DIR
BIN_DIR = _fixtures.BIN_DIR
BUILD_DIR = Path(os.environ.get("MACSIM_BUILD_DIR", BIN_DIR.parent))


def readable_by_all(path):
    """Opens a temporary folder (0700) to other users: the tests run programs as `nobody`."""
    os.chmod(path, 0o755)
    return path
