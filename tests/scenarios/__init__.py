"""Tests of acordcs.scenarios and acordcs-gen test."""
