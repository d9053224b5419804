"""Tests of the free body's dispersion study (stability.free_body.dispersion)."""
