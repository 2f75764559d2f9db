"""Tests of acordcs.model."""
