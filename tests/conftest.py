"""Shared fixtures: the paper arms, their Drake plants, random in-limit configurations."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from armlab.models import ARMS, get_arm
from armlab.models.arm import Arm

ARM_NAMES = list(ARMS)


@functools.cache
def arm_and_plant(name: str):
    """(arm, plant, context) for a paper arm with default parameters, built once per session."""
    arm = get_arm(name)
    plant = arm.make_plant()
    return arm, plant, plant.CreateDefaultContext()


def random_q(arm: Arm, rng: np.random.Generator, size: int) -> np.ndarray:
    """``size`` random configurations within the joint limits (unlimited joints: ±2π)."""
    return rng.uniform(*arm.limit_arrays(unlimited=2 * np.pi), size=(size, arm.n))


@pytest.fixture(params=ARM_NAMES)
def arm_name(request) -> str:
    """Each paper arm's name in turn."""
    return request.param


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: failures are reproducible."""
    return np.random.default_rng(20261123)
