"""A simulated WebLab for the paper's section 4 experiment, in virtual time.

A mobile robot follows a coloured stripe on the floor using only its on-board camera; the user's
control program (the Navigator) runs over the user's network. The modules, one job each:

- :mod:`.floor`: the 4 x 3 m floor raster (5 mm/px), the stripe path and its finish line;
- :mod:`.robot`: the pymunk differential-drive robot, advanced lazily on a fixed physics grid;
- :mod:`.camera`: the 160 x 120 on-board camera (opencv ``warpPerspective`` from the floor) and
  the panoramic camera's frame size;
- :mod:`.detector` and :mod:`.steering`: the user's stripe detector and pure-pursuit steering;
- :mod:`.network`: the access networks as connector QoS, and the access link they share;
- :mod:`.world`: one run's lab (robot, sensors, users, scripted disturbances) and the hook
  components find it by (:func:`weblab_sim.world.current`);
- :mod:`.experiment`: ``run(profile, seed, condition) -> metrics``, the generated application
  assembled on a :class:`~acordcs.runtime.clock.VirtualClock`;

Everything happens in the clock's time (``now``, ``sleep``, ``call_later``, ``call_every``) and
draws from ``clock.rng(purpose)``, one stream per purpose: a run is deterministic for its seed.

**Tuned to the paper's Table 1** (so that the adaptive runs' cycle rates come out near 0.90, 1.46
and 1.72 per second): the one-way latencies (residential 115 ms, campus 25 ms, LAN 0.5 ms) and
jitters, the WebLab server's grab time (0.33 s), the user's CPU time per cycle (0.25 s), and the
panoramic camera's frame size (25 KB: 12 fps overfill a 2 Mbit/s line).

**From the paper**: the residential line's 2 Mbit/s, the five-step control cycle, the three
retries before the user is asked for, the rule tables' two example rules.

**Fixed beforehand, not tuned**: the path (six segments, 6.4 m, turns of 75, 80, 45, -100 and
-70 degrees), the floor, the stripe's colour and width, the camera's footprint and size, the
robot (330 mm wheel base, 4 kg, 300 mm/s wheels), the detector and the 300 mm pure-pursuit
distance, campus 10 Mbit/s and LAN 100 Mbit/s, the 48 KB downlink buffer, the recovery's
backing speed and speed cap, the person's patience (6 cycles) and delay (10 s), the conditions'
fixed speeds (50 and 150 mm/s). The fuzzy terms and rules are the model's (``weblab.xmi``; its
README says which terms were tuned to Table 1).
"""
