"""The built-in targets: ``config`` (XSLT 3.0) and ``rules`` (Python). Importing this package
registers them (:func:`acordcs.codegen.registry.targets` does)."""

from acordcs.codegen.targets import config, rules

BUILTIN = (config.TARGET, rules.rules)

__all__ = ["BUILTIN"]
