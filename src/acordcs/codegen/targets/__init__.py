"""The built-in targets: ``config`` (XSLT 3.0), ``java`` (XSLT 3.0), ``python`` (XSLT 3.0, after a
check of the names in Python), ``rules`` (Python: the engines' compiled policy sets) and ``shell``
(XSLT 3.0, after the same check: POSIX sh scripts). Importing this package registers them
(:func:`acordcs.codegen.registry.targets` does)."""

from acordcs.codegen.targets import config, java, python, rules, shell

BUILTIN = (config.TARGET, java.TARGET, python.python, rules.rules, shell.shell)

__all__ = ["BUILTIN"]
