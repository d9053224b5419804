"""Tests of the heavy top's studies (stability.heavy_top.studies)."""
