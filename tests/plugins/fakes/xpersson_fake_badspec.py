"""A plugin with a malformed ParamSpec: the default lies outside the bounds."""

from xpersson.plugins import Boundary, ParamSpec


class BadSpecWall(Boundary):
    summary = "malformed parameter declaration"
    parameters = {"s": ParamSpec("Pa", default=-1.0, bounds=(0.0, None))}
