"""Shared fixtures. The package is imported from the source tree
(bindings/python) and loads the library named by GEOM_LIBRARY."""

import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


@pytest.fixture(scope="session")
def data_dir():
    return os.environ.get("GEOM_TEST_DATA", os.path.join(REPO, "data"))


@pytest.fixture(scope="session")
def include_dir():
    return os.environ.get("GEOM_INCLUDE_DIR", os.path.join(REPO, "libgeom", "include", "geom"))


@pytest.fixture(scope="session")
def shared_data_dir():
    return os.environ.get("GEOM_SHARED_DATA", os.path.join(REPO, "tests", "data"))
