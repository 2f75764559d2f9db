"""The code generator behind ``acordcs-gen build``: targets by name, run over the application
descriptor, their files written into an output directory only where they changed.

- :mod:`.registry`: :func:`target` (Python targets, by decorator), :func:`xslt_target` (XSLT 3.0
  stylesheets), the entry-point group ``acordcs.targets`` for other packages' targets;
- :mod:`.context`: what a target gets (:class:`TargetContext`) and gives back (``emit``);
- :mod:`.pipeline`: :func:`build` (read, validate, describe, transform, write);
- :mod:`.writer`, :mod:`.manifest`, :mod:`.paths`, :mod:`.headers`, :mod:`.xslt`: writing only what
  changed, the manifest, safe paths, file headers, running Saxon;
- :mod:`.targets`: the built-in targets ``config``, ``java``, ``python`` and ``rules``.

::

    from acordcs.codegen import build

    result = build("samples/weblab/weblab.xmi", "build/weblab")  # every target
    [c.path for c in result.plan.changes]
"""

from acordcs.codegen.context import GeneratedFile, TargetContext
from acordcs.codegen.errors import BuildError
from acordcs.codegen.paths import MANIFEST
from acordcs.codegen.pipeline import BuildResult, build
from acordcs.codegen.registry import ENTRY_POINT_GROUP, Target, target, targets, xslt_target

__all__ = [
    "ENTRY_POINT_GROUP",
    "MANIFEST",
    "BuildError",
    "BuildResult",
    "GeneratedFile",
    "Target",
    "TargetContext",
    "build",
    "target",
    "targets",
    "xslt_target",
]
