"""Tests of stability.free_body.stability_map."""
