"""Tests of the text notation (acordcs.notation) and acordcs-gen convert."""
