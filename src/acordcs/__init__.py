"""ACORD-CS: a domain-independent middleware framework for context-aware applications."""

__version__ = "0.1.0"
