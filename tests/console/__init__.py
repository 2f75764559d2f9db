"""Tests of acordcs.console: the console of any running application."""
