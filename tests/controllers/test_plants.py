"""Tests of controllers.plants: every plant, importable from one place."""

from __future__ import annotations

from optraj import controllers
from optraj.controllers import dynamic_plant, kinematic_plant, plant, plants


def test_the_plants_are_the_classes_of_their_modules():
    assert plants.KinematicPlant is kinematic_plant.KinematicPlant
    assert plants.DynamicPlant is dynamic_plant.DynamicPlant
    assert plants.Plant is plant.Plant and plants.PlantState is plant.PlantState
    assert controllers.DynamicPlant is plants.DynamicPlant
    assert issubclass(plants.KinematicPlant, plants.Plant)
    assert issubclass(plants.DynamicPlant, plants.Plant)
