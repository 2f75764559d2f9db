"""Tests of the samples (samples/): well-formed, BOUML-shaped, and running."""
