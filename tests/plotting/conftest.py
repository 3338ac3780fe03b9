"""Plotting tests draw off-screen (Agg) and share small synthetic results (no solver run)."""

import matplotlib
import pytest

matplotlib.use("Agg")

import synthetic_results  # noqa: E402  (tests/plotting is on sys.path for its tests)


@pytest.fixture(scope="session")
def pem():
    return synthetic_results.pem_response()


@pytest.fixture(scope="session")
def mc():
    return synthetic_results.mc_response()


@pytest.fixture(scope="session")
def th():
    return synthetic_results.time_history()
