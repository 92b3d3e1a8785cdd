"""Test options: ``--long`` runs the long variants of the stress tests (``stress`` marker)."""

import pytest


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--long",
        action="store_true",
        default=False,
        help="run the long variants of the stress tests",
    )


@pytest.fixture
def long_run(request: pytest.FixtureRequest) -> bool:
    """True when the long variants of the stress tests were asked for (``--long``)."""
    return bool(request.config.getoption("--long"))
