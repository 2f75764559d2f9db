"""The paper's two case-study policies (``tests/support/fuzzy_bases.py``) and their FCL twins
define the same policies."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.support.fuzzy_bases import bandwidth_engine, speed_engine

FCL_DIR = Path(__file__).parent / "fcl"


@pytest.mark.parametrize(
    ("fcl_file", "factory", "ruleset", "inputs", "output"),
    [
        ("speed.fcl", speed_engine, "speed", ("cycleRate", "angle"), "speed"),
        ("bandwidth.fcl", bandwidth_engine, "bandwidth", ("cycleRate", "numUsers"), "fps"),
    ],
)
def test_fcl_files_define_the_same_policies(fcl_file, factory, ruleset, inputs, output):
    from acordcs.engines.fuzzy.fcl import read_fcl

    (from_file,) = read_fcl((FCL_DIR / fcl_file).read_text(), filename=fcl_file).values()
    ours = factory()
    rng = np.random.default_rng(7)
    va, vb = (ours.variables[name] for name in inputs)
    a, b = rng.uniform(va.lo, va.hi, 300), rng.uniform(vb.lo, vb.hi, 300)
    got = from_file.batch(ruleset, {inputs[0]: a, inputs[1]: b})[output]
    want = ours.batch(ruleset, {inputs[0]: a, inputs[1]: b})[output]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
