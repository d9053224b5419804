"""Tests of the rolling study (stability.rolling.studies)."""
