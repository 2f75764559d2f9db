"""The WebLab experiment of ``make demo``: the paper's Table 1 reproduced in simulation.

:mod:`.grid` runs every (condition, profile, seed) in worker processes with a progress bar;
:mod:`.summary` turns runs into means and spreads, the paper's table beside ours and the claims
checked; :mod:`.plots` draws the figures; :mod:`.report` writes results.json, results.csv and
report.html. ``python -m weblab_experiment --help`` for the options.
"""
