"""Fixtures of the tests of murus.studies (inputs in studies_inputs.py)."""

import pytest
from studies_inputs import small_study, synthetic_records


@pytest.fixture(scope="session")
def records():
    return synthetic_records()


@pytest.fixture
def plan(records):
    return small_study(records).plan()
