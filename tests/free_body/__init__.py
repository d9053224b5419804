"""Tests of the free rigid body (stability.free_body)."""
