"""The cyclic garbage collector is paused while a block is stacked and its state restored
after, also on an error and when it was off already."""

from __future__ import annotations

import gc

import pytest

from xpersson.sweep.fast import _collector_paused


def test_collector_paused_then_restored():
    assert gc.isenabled()
    with _collector_paused():
        assert not gc.isenabled()
    assert gc.isenabled()
    with pytest.raises(RuntimeError), _collector_paused():
        raise RuntimeError("a failing block")
    assert gc.isenabled()
    gc.disable()
    try:
        with _collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()  # off before: left off
    finally:
        gc.enable()
