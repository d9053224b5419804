"""Tests of the engine artefacts study (stability.engine_body.studies)."""
