import pathlib

import pytest

REPO_ROOT = pathlib.Path(__file__).resolve().parents[4]


@pytest.fixture
def repo_root():
    return REPO_ROOT
