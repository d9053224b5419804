"""Tests of the estimators on ensembles (stability.analysis)."""
