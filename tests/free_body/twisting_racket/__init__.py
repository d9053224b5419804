"""Tests of stability.free_body.twisting_racket."""
