"""Options of the markov methods (``markov`` walkers and ``markov_ck`` kernel), shared by both
modules so that neither imports the other for them."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["markov_options", "GAP_STEPS"]

_DEFAULTS = {"walkers": 100_000, "seed": 0, "steps_per_decade": 64, "chunk": 1_000_000}
GAP_STEPS = 6.0  # sqrt(2 dtau) <= gap / GAP_STEPS when two walls are present


def markov_options(options: dict[str, Any]) -> dict[str, Any]:
    """Checked options of the markov methods (defaults filled in).

    Raises
    ------
    ValueError
        Naming the option and its allowed range.
    """
    allowed = {*_DEFAULTS, "mode", "nodes", "window_k", "ratio"}
    unknown = sorted(set(options) - allowed)
    if unknown:
        raise ValueError(
            f"options: unknown keys {unknown} for the markov methods; allowed {sorted(allowed)}"
        )
    out = {**_DEFAULTS, **{k: v for k, v in options.items() if v is not None}}
    for key, lo in (("walkers", 1), ("steps_per_decade", 1), ("chunk", 1)):
        val = out[key]
        if isinstance(val, bool) or not isinstance(val, int | np.integer) or val < lo:
            raise ValueError(f'options["{key}"] [1] must be an integer >= {lo}; got {val!r}')
    seed = out["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f'options["seed"] [1] must be an integer >= 0; got {seed!r}')
    return out
