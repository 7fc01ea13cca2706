"""A sweep written to a folder as a transaction: a lock, an identity, resume.

A run into a folder

1. takes the folder's lock (``.xpersson.lock``, an advisory ``flock`` that dies with the process):
   of two runs into one folder exactly one proceeds, the other gets a
   :class:`~xpersson.errors.FolderBusyError` (CLI: exit 2). On a file system without ``flock``
   (``ENOLCK``, ``EOPNOTSUPP``: some network file systems) the run proceeds unlocked and an
   :class:`~xpersson.XperssonWarning` names the folder and the risk (two runs into it at once
   would mix their parts); any other error of the lock is raised;
2. compares the study with what the folder holds: the *study hash* is the sha256 of the scene
   with every swept parameter as a list of SI values (:meth:`SweepPlan.scene_lists`), the
   contents of the files it names and the xpersson version. A folder holding another study is
   refused unless ``overwrite``; the same study is resumed (by default, or with ``resume=True``);
3. writes the index with ``state = "running"`` before any part (so an interrupted run is never
   mistaken for a complete one) and, when overwriting, removes the old parts;
4. reuses every part of the same study that verifies (checksums, identity, coordinates) and
   solves only the missing or damaged blocks; the blocks are cut as the first run cut them;
5. writes the complete index in one atomic step and releases the lock.

Every part carries the study hash and the id of the run that wrote it; :func:`.parts.open_parts`
checks both against the index. A resumed study equals an uninterrupted one: the same blocks,
the same points, the same stored bytes for every reused part.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import uuid
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..archive import file_digest, read
from ..errors import ArchiveError, FolderBusyError, XperssonWarning
from ..provenance import version
from .blocks import PART_ATTR, Block, BlockResult, _digests
from .parts import INDEX, PART_NAME, part_name, read_index_file, write_index
from .plan import SweepPlan

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no lock (documented)
    fcntl = None  # type: ignore[assignment]

__all__ = ["LOCK", "study_hash", "Transaction"]

LOCK = ".xpersson.lock"


def study_hash(plan: SweepPlan) -> str:
    """sha256 of the study: its scene (swept lists in SI), the files it names, the version."""
    data = plan.scene_lists()
    files: dict[str, str] = {}
    base = Path(plan.scene.source).parent if plan.scene.source else Path(".")
    _file_digests(data, base, files)
    payload = {"scene": data, "files": files, "xpersson": version()}
    text = json.dumps(payload, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def _file_digests(node: Any, base: Path, out: dict[str, str]) -> None:
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "file" and isinstance(value, str):
                path = Path(value) if Path(value).is_absolute() else base / value
                with contextlib.suppress(OSError):
                    out[value] = file_digest(path)
            else:
                _file_digests(value, base, out)


@dataclass
class Transaction:
    """One run into a sweep folder (see the module's docstring); created by :meth:`begin`."""

    folder: Path
    study: str
    run: str
    layout: dict[str, int]
    mode: str
    fd: int | None = None
    damaged: list[str] = field(default_factory=list)
    #: sha256 of the parts an earlier run recorded (block number -> digest): a resumed run
    #: reuses a part only when its bytes are still these (attributes carry no fletcher32)
    known: dict[str, str] = field(default_factory=dict)

    @classmethod
    def begin(
        cls,
        folder: str | os.PathLike[str],
        plan: SweepPlan,
        layout: dict[str, int],
        *,
        resume: bool | None = None,
        overwrite: bool = False,
    ) -> Transaction:
        """Lock ``folder``, decide fresh / resume / overwrite, invalidate the index.

        Parameters
        ----------
        folder : path-like
            The sweep folder (created when missing).
        plan : SweepPlan
            The study.
        layout : dict
            ``points_per_block`` and ``multiple`` of :func:`.blocks.blocks_of` for a new run
            (a resumed run keeps the folder's).
        resume : bool or None
            ``None``: resume when the folder holds this study; ``True``: it must; ``False``:
            never reuse parts (a folder holding anything then needs ``overwrite``).
        overwrite : bool
            Start over whatever the folder holds (only its index and parts are removed).

        Raises
        ------
        FolderBusyError
            Another run holds the folder.
        ArchiveError
            The folder holds another study, an unreadable index or other files, and
            ``overwrite`` is false; or ``resume=True`` and there is nothing to resume.
        """
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        fd = _acquire(folder)
        txn = cls(folder, study_hash(plan), uuid.uuid4().hex, dict(layout), "fresh", fd)
        try:
            txn._decide(resume, overwrite)
            write_index(folder, {**txn.header(plan, "running"), "known": txn.known})
            if txn.mode == "overwrite":
                for old in folder.glob("part-*.nc"):
                    if PART_NAME.fullmatch(old.name):
                        old.unlink(missing_ok=True)
        except BaseException:
            txn.release()
            raise
        return txn

    def _decide(self, resume: bool | None, overwrite: bool) -> None:
        folder = self.folder
        if overwrite:
            self.mode = "overwrite"
            return
        try:
            index = read_index_file(folder)
        except FileNotFoundError:
            index = None
        except ArchiveError as exc:
            raise ArchiveError(
                f"{exc}; pass overwrite=True (CLI: --overwrite) to replace it"
            ) from None
        if index is None:
            others = sorted(p.name for p in folder.iterdir() if not p.name.startswith("."))
            if others:
                raise ArchiveError(
                    f"{folder} is not empty ({others[0]}, ...) and holds no sweep index; "
                    "choose an empty folder or pass overwrite=True (CLI: --overwrite)"
                )
            if resume:
                raise ArchiveError(f"{folder}: nothing to resume (no {INDEX})")
            return
        if index.get("study") != self.study:
            raise ArchiveError(
                f"{folder} holds a different study (scene hash {str(index.get('study'))[:12]} "
                f"here, {self.study[:12]} now); pass overwrite=True (CLI: --overwrite) to "
                "replace it, or choose another folder"
            )
        if resume is False:
            raise ArchiveError(
                f"{folder} holds this study already; resume it (the default) or pass "
                "overwrite=True (CLI: --overwrite) to solve it again"
            )
        layout = index.get("layout")
        if not (
            isinstance(layout, dict)
            and all(type(layout.get(k)) is int and layout[k] >= 1 for k in self.layout)
        ):
            raise ArchiveError(f"{folder / INDEX}: malformed layout; pass overwrite=True")
        self.layout = {k: layout[k] for k in self.layout}
        self.known = _known_digests(index)
        self.mode = "resume"

    def header(self, plan: SweepPlan, state: str) -> dict[str, Any]:
        """The index fields that identify the run (without parts and attributes)."""
        return {
            "state": state,
            "study": self.study,
            "run": self.run,
            "layout": self.layout,
            "dims": list(plan.dims),
            "shape": list(plan.shape),
            "coords": {
                name: [dim, np.asarray(values).tolist()]
                for name, (dim, values, _) in plan.coords().items()
            },
        }

    def part_attrs(self) -> dict[str, str]:
        """The identity every part of this run carries."""
        return {"study": self.study, "run": self.run}

    def reusable(self, blocks: list[Block]) -> dict[int, BlockResult]:
        """The blocks whose parts (of this study, verified) a resumed run keeps."""
        if self.mode != "resume":
            return {}
        out = {}
        for block in blocks:
            path = self.folder / part_name(block.number)
            if not path.is_file():
                continue
            try:
                want = self.known.get(str(block.number))
                if want is not None and file_digest(path) != want:
                    raise ArchiveError(f"{path}: differs from the checksum the study recorded")
                out[block.number] = _reuse(path, block, self.study)
            except ArchiveError as exc:
                self.damaged.append(str(exc))
        return out

    def complete(self, plan: SweepPlan, results: list[BlockResult], extra: dict[str, Any]) -> None:
        """Write the complete index (atomically)."""
        parts = [
            {
                "number": r.block.number,
                "grid_index": list(r.block.grid_index),
                "start": list(r.block.start),
                "stop": list(r.block.stop),
                "name": Path(str(r.part)).name,
                "run": r.run or self.run,
                "sha256": r.sha256 or file_digest(str(r.part)),
            }
            for r in results
        ]
        write_index(self.folder, {**self.header(plan, "complete"), "parts": parts, **extra})

    def release(self) -> None:
        """Release the lock (the lock file stays: removing it would race other runs)."""
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None


def _known_digests(index: dict[str, Any]) -> dict[str, str]:
    """Part digests an index holds: a complete one's ``parts``, a running one's ``known``."""
    known = index.get("known")
    out = {str(k): v for k, v in known.items()} if isinstance(known, dict) else {}
    for entry in index.get("parts") or ():
        if isinstance(entry, dict) and isinstance(entry.get("sha256"), str):
            out[str(entry.get("number"))] = entry["sha256"]
    return {k: v for k, v in out.items() if isinstance(v, str)}


def _acquire(folder: Path) -> int | None:
    fd = os.open(folder / LOCK, os.O_RDWR | os.O_CREAT, 0o666)
    if fcntl is None:  # pragma: no cover
        return fd
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise FolderBusyError(
            f"{folder}: another run is writing into this folder; wait for it to finish "
            "or choose another folder"
        ) from None
    except OSError as exc:
        if exc.errno not in _NO_LOCKS:
            os.close(fd)
            raise
        warnings.warn(
            f"{folder}: the file system does not support locks ({errno.errorcode[exc.errno]}); "
            "this run writes into the folder without its lock, so a second run started into "
            "the same folder at the same time would mix its parts with this one's",
            XperssonWarning,
            stacklevel=5,
        )
    return fd


#: errno of ``flock`` on a file system without locks (the run then proceeds unlocked)
_NO_LOCKS = frozenset({errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOTSUP})


def _reuse(path: Path, block: Block, study: str) -> BlockResult:
    """A verified part of ``study`` as the result of ``block`` (no solving)."""
    ds = read(path)  # checksums of every variable
    try:
        info = json.loads(ds.attrs.get(PART_ATTR, "{}"))
    except ValueError:
        info = {}
    if info.get("study") != study or info.get("number") != block.number:
        raise ArchiveError(f"{path}: part of another study or block")
    for name, (_, values, _) in block.coords.items():
        if name not in ds.variables or not np.array_equal(ds[name].values, values):
            raise ArchiveError(f"{path}: coordinate {name!r} differs")
    status = np.asarray(ds["point_status"].values, dtype=np.int8).reshape(block.shape)
    failed = status.ravel() == 2
    missing = {n: set(v) for n, v in (info.get("missing") or {}).items()}
    names = set(ds.variables)
    present = [
        None if failed[k] else {n for n in names if k not in missing.get(n, ())}
        for k in range(block.size)
    ]
    digests = _digests(present, ds, block) if not failed.all() else {}
    messages = {int(k): v for k, v in (info.get("messages") or {}).items()}
    result = BlockResult(block, None, str(path), status, messages, digests, info.get("solver", []))
    result.sha256 = file_digest(path)
    result.run = str(info.get("run"))
    result.fast_path_failures = list(info.get("fast_path_failures") or [])
    return result
