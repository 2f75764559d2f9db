"""The ACORD-CS rule language: one grammar (``rules.lark``), one parser (:mod:`.parser`: its fast
reader :mod:`.fast`, and :mod:`.lark_parser`, lark's LALR(1) parser of the grammar, for what the
reader declines and every error) and the immutable tree it builds (:mod:`.tree`), shared by the
model checks and the rule engines."""

from acordcs.rules.parser import *  # noqa: F403  (the parser's __all__ is this package's interface)
from acordcs.rules.parser import __all__  # noqa: F401
