"""Tests of acordcs."""
