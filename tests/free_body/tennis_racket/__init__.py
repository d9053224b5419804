"""Tests of stability.free_body.tennis_racket."""
