"""The CLIPS rule engine (through clipspy) behind the paper's four calls: see :mod:`.clips_engine`."""

from acordcs.engines.clips.clips_engine import ClipsEngine, FireError
from acordcs.engines.clips.clips_from_plan import engine_for_plan

__all__ = ["ClipsEngine", "FireError", "engine_for_plan"]
