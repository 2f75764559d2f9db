"""The ACORD-CS runtime: containers, components, connectors, monitors, policy sets and rule engines."""
