"""Tests of the figures' style and checks (stability.plotting)."""
