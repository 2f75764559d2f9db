"""Tests of acordcs.cli."""
