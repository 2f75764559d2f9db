"""The generator's built-in XSLT 3.0 stylesheets, as package data.

- ``transform-target.xsl``: the driver every XSLT target runs through (:mod:`acordcs.generator.xslt`);
- ``config.xsl``, ``java.xsl``, ``python.xsl``, ``shell.xsl`` (with ``shell-functions.xsl`` and
  ``shell-hosts.xsl``): the built-in targets' stylesheets, registered in :mod:`acordcs.generator.targets`;
- ``java-api/*.java``: the small Java API the ``java`` target copies beside the classes it writes.

Nothing here is Python to import: the stylesheets are read by Saxon, found with
``importlib.resources.files("acordcs.transforms")``.
"""
