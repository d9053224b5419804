"""Tests of rolling and slipping (stability.rolling)."""
