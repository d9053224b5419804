"""Tests of the asteroid study (stability.asteroid.studies)."""
