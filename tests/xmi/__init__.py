"""Tests of acordcs.xmi."""
