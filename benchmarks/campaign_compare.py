"""Compare two validation-campaign result files record by record, bitwise on the numbers.

Records are matched by scene ``id`` and must come in the same order; every field is compared
exactly (floats by their bits: ``json`` writes the shortest repr that round-trips, so equal
text is equal bits; NaN equals NaN) except the run's own ``seconds`` and ``provenance`` (date).
Exit status 1 and the first differences on a mismatch.

Usage::

    python benchmarks/campaign_compare.py results/campaign_dask_serial.jsonl \\
        results/campaign_dask_cluster.jsonl
"""

from __future__ import annotations

import argparse
import json
import math
import struct
import sys
from pathlib import Path
from typing import Any

IGNORED = ("seconds", "provenance")


def _bits(x: float) -> bytes:
    return b"nan" if math.isnan(x) else struct.pack("<d", x)


def diff(a: Any, b: Any, where: str = "") -> list[str]:
    """Paths where ``a`` and ``b`` differ (floats compared by their bits)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{where}.{k}: only in one" for k in sorted(set(a) ^ set(b))]
        for k in sorted(set(a) & set(b)):
            out += diff(a[k], b[k], f"{where}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: length {len(a)} != {len(b)}"]
        pairs = enumerate(zip(a, b, strict=True))
        return [d for i, (x, y) in pairs for d in diff(x, y, f"{where}[{i}]")]
    if isinstance(a, float) and isinstance(b, float):
        return [] if _bits(a) == _bits(b) else [f"{where}: {a!r} != {b!r}"]
    return [] if type(a) is type(b) and a == b else [f"{where}: {a!r} != {b!r}"]


def load(path: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def compare(a: list[dict[str, Any]], b: list[dict[str, Any]]) -> list[str]:
    """Differences between two campaigns' records (empty: equal)."""
    ids_a, ids_b = [r["id"] for r in a], [r["id"] for r in b]
    if ids_a != ids_b:
        return [f"scene order differs: {ids_a} != {ids_b}"]
    out = []
    for ra, rb in zip(a, b, strict=True):
        strip = [{k: v for k, v in r.items() if k not in IGNORED} for r in (ra, rb)]
        out += diff(*strip, where=ra["id"])
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a", type=Path)
    ap.add_argument("b", type=Path)
    args = ap.parse_args(argv)
    a, b = load(args.a), load(args.b)
    diffs = compare(a, b)
    secs = [sum(r["seconds"] for r in recs) for recs in (a, b)]
    print(f"{len(a)} vs {len(b)} records; summed scene seconds {secs[0]:.1f} vs {secs[1]:.1f}")
    if diffs:
        print(f"{len(diffs)} differences, first: " + "\n".join(diffs[:20]))
        sys.exit(1)
    print("equal: every number bitwise identical (seconds and provenance ignored)")


if __name__ == "__main__":
    main()
