"""Tests of the documentation: the README says what the tools do."""
