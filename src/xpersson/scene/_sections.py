"""A scene section of plain values converted once per process (the same declarations and
values: one cache look-up instead of one per value)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..cache import Cache
from ..specs import ParamSpec
from ._convert import convert_params

__all__ = ["convert_section"]


def convert_section(
    specs: Mapping[str, ParamSpec], raw: Mapping[str, Any], where: str
) -> dict[str, Any]:
    """:func:`~xpersson.scene._convert.convert_params` of section ``where``: a section of
    several plain scalar values (numbers, strings, bools; no array parameter) is converted
    once per process for the same declarations and values (keyed on the specs' content keys
    and each value with its type), the others each time; the defaults are the specs' own
    objects, as ``convert_params`` gives them. A failing conversion raises its own message
    every time (an error is never kept)."""
    plain = len(raw) > 1 and all(
        type(v) in (str, float, int, bool) and n in specs and not specs[n].array
        for n, v in raw.items()
    )
    if not plain:
        return convert_params(specs, raw, where)
    # one flat tuple (the specs' count first: unambiguous), keyed without nested tuples; the
    # type with each value: True and 1 (equal keys) convert differently
    key: list[Any] = [where, len(specs)]
    for n, s in specs.items():
        key += (n, s.cache_key())
    for n, v in raw.items():
        key += (n, type(v).__name__, v)

    def convert() -> dict[str, Any]:
        out = convert_params(specs, raw, where)
        return {n: out[n] for n in raw}

    found = _SECTIONS.get(tuple(key), convert)
    return {n: found[n] if n in found else s.default for n, s in specs.items()}


_SECTIONS = Cache(
    "scene.sections",
    scope="process",
    maxsize=256,
    doc="a scene section's plain scalar values in SI by their ParamSpecs (floats, as given)",
)
