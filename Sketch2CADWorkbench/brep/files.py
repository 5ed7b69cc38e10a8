# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writing files so that nothing is lost: the one home of atomic writes.

A file is written under a temporary name of its own in the same folder (unique per
writer, so two writers of one path never share one), flushed to disk, given the mode of
the file it replaces (or the umask's for a new one), and only then renamed over the
target: a reader sees the old file or the new one, never a part. A writer killed
midway leaves only its temporary, `.NAME.sketch2cad-tmp-PID-XXXX.SUFFIX`, which the next
write of that path removes once process PID is gone. Several outputs of one command are
moved into place together, only when all of them were written (`atomic_outputs`).
Standard library only: every layer uses it.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

MARK = ".sketch2cad-tmp-"


def temporary_path(path: str | Path) -> Path:
    """A fresh temporary name beside `path`, ending in the same suffix (writers such as
    OCCT's and OpenCV's choose the format by it)."""
    path = Path(path)
    return path.with_name(f".{path.name}{MARK}{os.getpid()}-{secrets.token_hex(4)}{path.suffix}")


def remove_stale_temporaries(path: str | Path) -> None:
    """Remove the temporaries of `path` left by writers that no longer run."""
    path = Path(path)
    prefix = f".{path.name}{MARK}"
    try:
        names = os.listdir(path.parent)
    except OSError:
        return
    for name in names:
        if name.startswith(prefix):
            pid = name[len(prefix) :].split("-")[0]
            if pid.isdigit() and not _running(int(pid)):
                with suppress(OSError):
                    os.unlink(path.parent / name)


def _running(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _mode_for(path: Path) -> int:
    try:
        return path.stat().st_mode & 0o7777
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _sync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _commit(tmps: list[Path], paths: list[Path]) -> None:
    """Make the finished temporaries the files at `paths`: every one checked, given its
    mode and flushed to disk before the first is renamed."""
    for tmp, path in zip(tmps, paths, strict=True):
        if not tmp.exists():
            raise OSError(f"{path}: the writer produced no file")
        os.chmod(tmp, _mode_for(path))
        _sync(tmp)
    for tmp, path in zip(tmps, paths, strict=True):
        os.replace(tmp, path)
    for folder in {p.parent if str(p.parent) else Path(".") for p in paths}:
        # some file systems cannot sync a folder; the renames are done
        with contextlib.suppress(OSError):
            _sync(folder)


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """`with atomic_path(p) as tmp:` write the file at `tmp`; on a normal exit it
    replaces `p`, on an exception `p` is untouched and `tmp` removed."""
    with atomic_outputs([path]) as tmps:
        yield tmps[0]


@contextmanager
def atomic_outputs(paths: list[str | Path]) -> Iterator[list[Path]]:
    """Temporaries for several outputs; all are moved into place when the block ends
    normally, none when it raises (and the temporaries are removed)."""
    paths = [Path(p) for p in paths]
    for p in paths:
        remove_stale_temporaries(p)
    tmps = [temporary_path(p) for p in paths]
    try:
        yield tmps
        _commit(tmps, paths)
    finally:
        for tmp in tmps:
            if tmp.exists():
                tmp.unlink()


def write_atomically(path: str | Path, data: str | bytes) -> None:
    """Write `data` (text as UTF-8) to `path` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.encode() if isinstance(data, str) else data)


def check_outputs(
    inputs: dict[str, str | Path | None], outputs: dict[str, str | Path | None]
) -> None:
    """Refuse outputs that would overwrite an input or each other, before any work.

    Args:
        inputs, outputs: option name -> path (None: not given).

    Raises:
        ValueError: naming the two options and the path.
    """
    seen = {Path(os.path.realpath(p)): name for name, p in inputs.items() if p is not None}
    for name, p in outputs.items():
        if p is None:
            continue
        key = Path(os.path.realpath(p))
        if key in seen:
            raise ValueError(
                f"{name} {p} is the same file as {seen[key]}: refused, so that "
                f"neither is lost; nothing was written"
            )
        seen[key] = name
