"""Tests of the integrators (stability.integrators), one module per family of methods."""
