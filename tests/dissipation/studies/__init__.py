"""Tests of the dissipation studies (stability.dissipation.studies)."""
