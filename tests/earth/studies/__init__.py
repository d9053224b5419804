"""Tests of the Earth's studies (stability.earth.studies)."""
