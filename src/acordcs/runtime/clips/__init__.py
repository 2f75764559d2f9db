"""The CLIPS rule engine (through clipspy) behind the paper's four calls: see :mod:`.engine`."""

from acordcs.runtime.clips.engine import ClipsEngine, FireError

__all__ = ["ClipsEngine", "FireError"]
