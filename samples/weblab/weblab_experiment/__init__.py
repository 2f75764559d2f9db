"""The WebLab experiment of ``make demo``: the paper's Table 1 reproduced in simulation.

:mod:`.grid` runs every (path, condition, profile, seed) in worker processes with a progress bar;
:mod:`.summary` turns runs into means, sample SDs and n, and checks the claims per path
(:mod:`.stats`: t intervals); :mod:`.differences` says where Table 1 and ours differ by more than
20% and why, with the measurements; :mod:`.tuning` is the tuning table (``tuning.toml``), which
the README and the report both render; :mod:`.display` formats figures; :mod:`.printed` is what
the command prints, :mod:`.plots` draws the figures (PNG, SVG, PDF), :mod:`.report` writes
results.json, results.csv and report.html. ``python -m weblab_experiment --help`` for the options.
"""
