"""Tests of the struck body's study (stability.struck.studies)."""
