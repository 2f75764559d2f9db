"""The code generator behind ``acordcs-gen build``: targets by name, run over the application
descriptor, their files written into an output directory only where they changed.

- :mod:`.describe`: the model read as the application descriptor the targets run over;
- :mod:`.target`: :func:`target` (Python targets, by decorator), :func:`xslt_target`
  (XSLT 3.0 stylesheets), the entry-point group ``acordcs.targets`` for other packages'
  targets;
- :mod:`.context`: what a target gets (:class:`TargetContext`) and gives back (``emit``);
- :mod:`.pipeline`: :func:`build` (read, validate, describe, transform, write);
- :mod:`.writer`, :mod:`.manifest`, :mod:`.paths`, :mod:`.headers`, :mod:`.regions`,
  :mod:`.xslt`: writing only what changed, the manifest, safe paths, file headers, the user's
  protected regions, running Saxon (the stylesheets are in :mod:`acordcs.transforms`);
- :mod:`.drift`: the user's classes compared with the model at each build;
- :mod:`.targets`: the built-in targets ``config``, ``java``, ``python``, ``rules`` and ``shell``,
  and :func:`~.targets.targets`, every target by name.

::

    from acordcs.generator import build

    result = build("samples/weblab/weblab.xmi", "build/weblab")  # every target
    [c.path for c in result.plan.changes]
"""

from acordcs.generator.errors import BuildError
from acordcs.generator.paths import MANIFEST
from acordcs.generator.pipeline import BuildResult, build
from acordcs.generator.target import ENTRY_POINT_GROUP, Target, target, xslt_target
from acordcs.generator.target_context import GeneratedFile, TargetContext

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
    "xslt_target",
]
