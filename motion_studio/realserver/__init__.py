"""Measuring against the real rcssserver3d 0.7.3: the server process in a private network namespace, the skill
cases and their runs on both servers, the transfer table, the match check, trace recording and the fixtures
they write. Paths are relative to the project (paths.py); nothing here runs in tests but the replays."""

from motion_studio.realserver.errors import FixtureError, RealServerError

__all__ = ["FixtureError", "RealServerError"]
