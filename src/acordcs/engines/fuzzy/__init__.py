"""ACORD-CS's fuzzy rule engine: the paper's four calls, named inference semantics, FCL in and out.

>>> from acordcs.engines.fuzzy import FuzzyEngine
>>> e = FuzzyEngine()  # mamdani: min/max, exact centroid
"""

from acordcs.engines.fuzzy.fcl import read_fcl, write_fcl
from acordcs.engines.fuzzy.fuzzy_engine import FuzzyEngine
from acordcs.engines.fuzzy.fuzzy_from_plan import engine_for_plan
from acordcs.engines.fuzzy.membership import Membership, make_membership
from acordcs.engines.fuzzy.semantics import FCL_DEFAULTS, MAMDANI, SAZONOV, Semantics
from acordcs.engines.fuzzy.variable import LinguisticVariable

__all__ = [
    "FCL_DEFAULTS",
    "MAMDANI",
    "SAZONOV",
    "FuzzyEngine",
    "LinguisticVariable",
    "Membership",
    "Semantics",
    "engine_for_plan",
    "make_membership",
    "read_fcl",
    "write_fcl",
]
