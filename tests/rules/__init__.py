"""Tests of acordcs.rules."""
