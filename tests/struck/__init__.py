"""Tests of the struck bat (stability.struck)."""
