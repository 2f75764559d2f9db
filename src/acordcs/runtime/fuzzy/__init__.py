"""ACORD-CS's fuzzy rule engine: the paper's four calls, named inference semantics, FCL in and out.

>>> from acordcs.runtime.fuzzy import FuzzyEngine
>>> e = FuzzyEngine()  # mamdani: min/max, exact centroid
"""

from acordcs.runtime.fuzzy.fcl import read_fcl, write_fcl
from acordcs.runtime.fuzzy.fuzzy_engine import FuzzyEngine
from acordcs.runtime.fuzzy.membership import Membership, make_membership
from acordcs.runtime.fuzzy.semantics import FCL_DEFAULTS, MAMDANI, SAZONOV, Semantics
from acordcs.runtime.fuzzy.variable import LinguisticVariable

__all__ = [
    "FCL_DEFAULTS",
    "MAMDANI",
    "SAZONOV",
    "FuzzyEngine",
    "LinguisticVariable",
    "Membership",
    "Semantics",
    "make_membership",
    "read_fcl",
    "write_fcl",
]
