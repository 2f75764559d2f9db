"""A browser console for any running application: ``acordcs-gen console APPDIR``.

What every console shares: the web server (:mod:`.web_app`: one page, one WebSocket, viewers'
slots, strikes, pacing), the checks every request passes and the headers every answer carries
(:mod:`.site_guard`), the fan-out to viewers that never waits for one (:mod:`.fanout`), the
strict reading of what a viewer sends (:mod:`.viewer_messages`), a running application reached
as its scripts run it (:mod:`.attaching`) and the server run in a thread (:mod:`.in_thread`).
The WebLab's console (``samples/weblab/weblab_console``) is a site on the same server.
"""
