# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writing files so that nothing is lost: the one home of atomic writes.

A file is written under a temporary name of its own in the same folder (unique per
writer, so two writers of one path never share one), flushed to disk, given the mode of
the file it replaces (or the umask's for a new one), and only then renamed over the
target: a reader sees the old file or the new one, never a part. A writer killed
midway leaves only its temporary, `.NAME.sketch2cad-tmp-PID-XXXX.SUFFIX`, which the next
write of that path removes once process PID is gone. Several outputs of one command are
moved into place together, only when all of them were written (`atomic_outputs`).

Where the path leads decides how it is written. A symbolic link (even a dangling one)
stays a link: the file it leads to is written, atomically, beside that file. A path
that is not a regular file (a device such as /dev/null, a FIFO, a terminal, or a
descriptor of a process such as /dev/stdout) cannot be replaced by a rename: it is
written directly, with the bytes the writer put in a temporary in the system's
temporary folder. A folder is refused. Errors name the path the user gave, never a
temporary, and a full disk is said to be one.

Input files are read up to a size cap (`read_capped`), so that a huge file or an endless
device is refused instead of filling the memory.
Standard library only: every layer uses it.
"""

from __future__ import annotations

import errno
import os
import re
import secrets
import stat
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

MARK = ".sketch2cad-tmp-"
# The largest input file read, in MB; the environment variable of that name raises it.
MAX_INPUT_MB = 64
MAX_INPUT_ENV = "SKETCH2CAD_MAX_INPUT_MB"


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


def _commit(tmps: list[Path], targets: list[tuple[Path, bool]], paths: list[Path]) -> None:
    """Make the finished temporaries the files at `targets`: every one checked, given its
    mode and flushed to disk before the first is renamed (a path written directly gets
    the temporary's bytes)."""
    for tmp, (target, direct), path in zip(tmps, targets, paths, strict=False):
        if not tmp.exists():
            raise OSError(f"{path}: the writer produced no file")
        if not direct:
            os.chmod(tmp, _mode_for(target))
            _sync(tmp)
    for tmp, (target, direct) in zip(tmps, targets, strict=False):
        if direct:
            _copy_into(tmp, target)
        else:
            os.replace(tmp, target)
    for folder in {t.parent for t, direct in targets if not direct}:
        # some file systems cannot sync a folder; the renames are done
        with suppress(OSError):
            _sync(folder)


def _copy_into(tmp: Path, target: Path) -> None:
    """Write the bytes of `tmp` into `target`, a device, FIFO or descriptor that exists:
    one of this process's descriptors (/dev/stdout: /proc/self/fd/1) through that
    descriptor itself, so that the bytes land where its next output will follow them."""
    own = re.fullmatch(rf"/proc/(?:self|{os.getpid()})/fd/(\d+)", str(target))
    if own:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:
                stream.flush()
        fd = os.dup(int(own.group(1)))
    else:
        fd = os.open(target, os.O_WRONLY | os.O_APPEND)
    try:
        with open(tmp, "rb") as src, os.fdopen(fd, "wb", closefd=False) as out:
            while chunk := src.read(1 << 20):
                out.write(chunk)
    finally:
        os.close(fd)


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """`with atomic_path(p) as tmp:` write the file at `tmp`; on a normal exit it
    replaces `p`, on an exception `p` is untouched and `tmp` removed."""
    with atomic_outputs([path]) as tmps:
        yield tmps[0]


@contextmanager
def atomic_outputs(paths: list[str | Path]) -> Iterator[list[Path]]:
    """Temporaries for several outputs; all are moved into place when the block ends
    normally, none when it raises (and the temporaries are removed).

    Raises:
        IsADirectoryError: a path is a folder.
        OSError: a temporary or a path could not be written; the message names the
            path given, and says so when the disk is full.
    """
    paths = [Path(p) for p in paths]
    targets = [destination(p) for p in paths]
    for target, direct in targets:
        remove_stale_temporaries(_beside(target, direct))
    tmps = [temporary_path(_beside(target, direct)) for target, direct in targets]
    try:
        try:
            yield tmps
            _commit(tmps, targets, paths)
        except OSError as e:
            raise _named(e, tmps, paths) from None
    finally:
        for tmp in tmps:
            if tmp.exists():
                tmp.unlink()


def destination(path: Path) -> tuple[Path, bool]:
    """Where writing `path` lands, and whether it is written directly (True: not a
    regular file, or a descriptor of a process) rather than replaced by a rename.

    Raises:
        IsADirectoryError: `path` is a folder.
    """
    try:
        st = os.stat(path)
    except OSError:
        st = None  # a new file, or a dangling link: its target is made
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "is a folder, not a file", str(path))
    if st is not None and not stat.S_ISREG(st.st_mode):
        return path, True
    hop = path
    for _ in range(40):  # the links' own chain: /dev/stdout -> /proc/self/fd/1
        if not hop.is_symlink():
            break
        hop = hop.parent / os.readlink(hop)
        if hop.is_absolute() and hop.parts[1:2] == ("proc",):
            return hop, True
    return Path(os.path.realpath(path)), False


def _beside(target: Path, direct: bool) -> Path:
    """The name temporaries of `target` are made from: beside it, or, for a path written
    directly (whose folder may be /dev), in the system's temporary folder."""
    return Path(tempfile.gettempdir()) / target.name if direct else target


def _named(e: OSError, tmps: list[Path], paths: list[Path]) -> OSError:
    """`e` told about the path the user gave instead of a temporary; its errno kept."""
    names = {str(t): str(p) for t, p in zip(tmps, paths, strict=False)}
    path = names.get(str(e.filename), str(e.filename) if e.filename else None)
    if e.errno in (errno.ENOSPC, errno.EDQUOT):
        text = f"{path or ', '.join(names.values())}: the disk is full (no space left)"
    elif path and e.strerror:
        text = f"{path}: cannot write: {e.strerror}"
    else:
        text = str(e)
        for t, p in names.items():
            text = text.replace(t, p)
    named = type(e)(text)
    named.errno = e.errno
    return named


def write_atomically(path: str | Path, data: str | bytes) -> None:
    """Write `data` (text as UTF-8) to `path` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.encode() if isinstance(data, str) else data)


def read_capped(path: str | Path) -> bytes:
    """The bytes of an input file, refused past MAX_INPUT_MB (or the environment
    variable MAX_INPUT_ENV's value, in MB) before more than that is read.

    Raises:
        OSError: the file cannot be read, or is larger than the cap (saying how to raise
            it).
    """
    cap = max_input_bytes()
    with open(path, "rb") as f:
        data = f.read(cap + 1)
    if len(data) > cap:
        raise OSError(
            errno.EFBIG,
            f"larger than {cap / 1e6:g} MB, the most read from an input (set "
            f"{MAX_INPUT_ENV} to read more)",
            str(path),
        )
    return data


def max_input_bytes() -> int:
    """The input size cap in bytes: MAX_INPUT_MB, or the environment's MAX_INPUT_ENV.

    Raises:
        ValueError: the environment variable is not a positive number.
    """
    text = os.environ.get(MAX_INPUT_ENV)
    try:
        mb = float(text) if text is not None else MAX_INPUT_MB
    except ValueError:
        mb = -1.0
    if not mb > 0 or mb == float("inf"):
        raise ValueError(f"{MAX_INPUT_ENV}={text!r}: expected a positive number of MB")
    return int(mb * 1e6)


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
        if os.path.isdir(p):
            raise ValueError(f"{name} {p} is a folder; give the file to write in it")
        key = Path(os.path.realpath(p))
        if key in seen:
            raise ValueError(
                f"{name} {p} is the same file as {seen[key]}: refused, so that "
                f"neither is lost; nothing was written"
            )
        seen[key] = name
