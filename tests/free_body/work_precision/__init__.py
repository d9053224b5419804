"""Tests of stability.free_body.work_precision."""
