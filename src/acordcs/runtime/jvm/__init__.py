"""Components tagged ``language=java``, hosted in their container's process through JPype: their
classes the build's, else compiled at start into a cache keyed by their sources' digest
(``javac_cache.py``), their operations' call timeout (``deadlines.py``), the
JVM started once per process and only for them (``machine.py``), the component hosted as a
Python one (``java_component.py``: :func:`java_factory`), the values crossing
(``java_values.py``), the Java names of the model's (:mod:`acordcs.java_names`), the errors
(``errors.py``). :func:`acordcs.runtime.assembly.assemble` imports it only for such a component."""

from acordcs.runtime.jvm.java_component import JavaComponent, java_factory

__all__ = ["JavaComponent", "java_factory"]
