"""Tests of the heavy top (stability.heavy_top)."""
