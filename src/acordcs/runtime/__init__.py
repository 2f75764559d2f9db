"""The ACORD-CS runtime: containers, components, connectors, monitors and policy sets, which host the rule engines of :mod:`acordcs.engines`."""
