"""The submit-time check of a cluster's workers (issue 38): every worker must have the scene's
plugin distributions at the client's versions; a mismatch is one line naming worker, module and
distribution. A fake client runs the probe as dask does: pickled (by value) and run elsewhere."""

from __future__ import annotations

import pickle
import subprocess
import sys
import textwrap
from importlib import metadata

import cloudpickle
import pytest

from xpersson.sweep._workers import (
    WorkerEnvironmentError,
    check_workers,
    ran_on,
    requirements,
)

RECORDS = [
    ({"distribution": "xpersson", "version": metadata.version("xpersson"),
      "class": "xpersson.builtin.elastic:ElasticCoefficient"}, "elastic"),
    ({"distribution": "xpersson-interface", "version": metadata.version("xpersson-interface"),
      "class": "xpersson_interface.plugins:Leakage"}, "leakage"),
]  # fmt: skip


class FakeClient:
    """``run`` pickles the function and its argument as distributed does and runs them in a
    fresh interpreter (``hide``: a top-level module that cannot be imported there)."""

    def __init__(self, workers: dict[str, str | None]):
        self.workers = workers  # address -> hidden module (None: a complete worker)

    def run(self, fn, arg):
        blob = cloudpickle.dumps((fn, arg))
        out = {}
        for address, hide in self.workers.items():
            code = textwrap.dedent(f"""
                import pickle, sys
                class Hide:
                    def find_spec(self, name, path=None, target=None):
                        if name.split(".")[0] == {hide!r}:
                            raise ModuleNotFoundError(name)
                sys.meta_path.insert(0, Hide())
                sys.modules.pop("xpersson", None)
                fn, arg = pickle.loads(sys.stdin.buffer.read())
                sys.stdout.buffer.write(pickle.dumps(fn(arg)))
            """)
            done = subprocess.run(
                [sys.executable, "-c", code], input=blob, capture_output=True, check=True
            )
            out[address] = pickle.loads(done.stdout)
        return out


def test_requirements_of_the_records_name_distribution_version_and_module():
    assert requirements(RECORDS) == {
        "xpersson": (metadata.version("xpersson"), "xpersson"),
        "xpersson-interface": (metadata.version("xpersson-interface"), "xpersson_interface"),
    }


def test_complete_workers_pass():
    check_workers(FakeClient({"tcp://a:1": None, "tcp://b:2": None}), RECORDS)


def test_a_worker_without_the_plugin_is_one_line_naming_it():
    client = FakeClient({"tcp://a:1": None, "tcp://b:2": "xpersson_interface"})
    with pytest.raises(WorkerEnvironmentError) as err:
        check_workers(client, RECORDS)
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith("worker tcp://b:2 cannot import the plugin")
    assert "'xpersson_interface'" in msg and "xpersson-interface" in msg


def test_the_probe_runs_on_a_worker_without_xpersson():
    """Sent by value: a worker that cannot import xpersson still answers (and is named)."""
    with pytest.raises(
        WorkerEnvironmentError, match="worker tcp://c:3 cannot import the plugin module 'xpersson' "
    ):
        check_workers(FakeClient({"tcp://c:3": "xpersson"}), RECORDS)


def test_another_version_on_a_worker_is_named():
    older = [({**RECORDS[1][0], "version": "0.0.1"}, "leakage")]
    with pytest.raises(
        WorkerEnvironmentError, match="has xpersson-interface .*, this client 0.0.1"
    ):
        check_workers(FakeClient({"tcp://a:1": None}), older)


def test_a_missing_distribution_says_not_installed():
    ghost = [
        ({"distribution": "xpersson-ghost", "version": "1.0", "class": "xpersson_ghost:G"}, "g")
    ]
    with pytest.raises(WorkerEnvironmentError, match="lacks the plugin module 'xpersson_ghost'"):
        check_workers(FakeClient({"tcp://a:1": None}), ghost)


def test_ran_on_says_where_and_what_was_asked():
    assert ran_on(None, None, 1) == "serial"
    assert ran_on("threads", "threads", 2) == "threads (2)"
    assert ran_on("tcp://h:8786", "tcp://h:8786", 3) == "tcp://h:8786 (3 workers)"
    assert ran_on("processes", None, 1).startswith("serial (asked: processes;")


def test_a_small_study_asked_for_processes_says_it_ran_serially():
    import warnings
    from pathlib import Path

    import xpersson

    root = Path(__file__).resolve().parents[2]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(
            root / "examples" / "elastic.toml",
            material__E=["5 MPa", "10 MPa"],
            output__pressure_pdf=False,
            scheduler="processes",
        )
    assert ds.attrs["xpersson_scheduler"] == (
        "serial (asked: processes; the study takes less than starting the workers)"
    )
