"""What the tests of scripts/ share: the rtm binary ctest builds."""

import os

import pytest


@pytest.fixture
def rtm():
    path = os.environ.get("RTM_BINARY", "")
    if not os.access(path, os.X_OK):
        pytest.skip("RTM_BINARY names no rtm executable (ctest sets it)")
    return path
