"""Tests of physics engines' update rules (stability.engine_body)."""
