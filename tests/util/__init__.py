"""Tests of the shared utilities (stability.util)."""
