"""Tests of acordcs.profile."""
