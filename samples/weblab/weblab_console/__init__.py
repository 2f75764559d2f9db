"""The WebLab console (the paper's Figure 3) in a browser: the cameras, the navigation map and the
teleoperation controls, plus what the paper's console never showed: the monitored context, each
policy set's last firing with its rules' degrees, the speed limit and frame rate over time, and
recoveries and user requests on a timeline.

:mod:`.session` runs the experiment (the generated application on a paced virtual clock) and
publishes what it shows; :mod:`.attached` does the same over the two-process application its
scripts started (``make live-console``), reached through :mod:`.remote` (the containers' observer
and management interfaces); :mod:`.showing` makes what both publish; :mod:`.pictures` draws the
cameras' pictures; :mod:`.hub` fans the experiment's output out to viewers without ever waiting
for one; :mod:`.commands` reads what a viewer sends, strictly; :mod:`.server` is the Starlette
application (one page, one WebSocket); :mod:`.serving` runs it on uvicorn in a thread (tests,
benchmark, screenshot); ``python -m weblab_console`` is ``make console`` (``--attach``: ``make
live-console``); :mod:`.screenshot` makes the docs' pictures.
"""
