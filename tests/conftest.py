"""Fixtures shared by the tests."""

import pytest

import stability


@pytest.fixture
def body123():
    """The test body of the literature notes, I = (1, 2, 3) kg m^2 (a mathematical body)."""
    return stability.RigidBody(1.0, 2.0, 3.0, physical=False)
