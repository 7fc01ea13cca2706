"""A plugin written for a future plugin API."""

from xpersson.plugins import Boundary


class FutureWall(Boundary):
    summary = "needs plugin API v99"
    api_version = 99
