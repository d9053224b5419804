"""Tests of the shared numerics (stability.core)."""
