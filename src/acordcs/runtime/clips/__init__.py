"""The CLIPS rule engine (through clipspy) behind the paper's four calls: see :mod:`.clips_engine`."""

from acordcs.runtime.clips.clips_engine import ClipsEngine, FireError

__all__ = ["ClipsEngine", "FireError"]
