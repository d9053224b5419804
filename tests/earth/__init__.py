"""Tests of the Earth (stability.earth)."""
