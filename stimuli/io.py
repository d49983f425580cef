"""File helpers: atomic writes, checked input files and reading point tables.

Every file the project writes goes through :func:`atomic_write`, so that an
interrupted run never leaves a half-written file under its final name. Every
file it reads is first checked by :func:`check_regular_file`: a FIFO, a device
(``/dev/zero``) or a socket would hang the reader or feed it without end, so
only regular files (or links to them) are read, and text inputs (CSV files,
configs) are bounded by :data:`MAX_TEXT_BYTES`.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import sys
import tempfile
from pathlib import Path

from attneave.stimuli.errors import InputError

__all__ = [
    "MAX_TEXT_BYTES",
    "temporary_directory",
    "replace_directory",
    "atomic_write",
    "check_regular_file",
]

#: Largest CSV or other text input read (bytes): 200 MB holds millions of
#: clicks or contour points; a larger file is a mistake (or ``/dev/zero``).
MAX_TEXT_BYTES = 200 * 1000**2


# Temporary files and directories are named .attneave-tmp-<pid>-h<host>-<random>-<final name>:
# no user file is named so, and cleanup (which deletes only names of this form) never touches a
# user's file. The pid and host tell a temporary of a live run from one that a killed run left.
TEMP_PREFIX = ".attneave-tmp-"
_TEMP_RE = re.compile(r"^\.attneave-tmp-[0-9]+-[A-Za-z0-9_]+-")
_OWNER_RE = re.compile(r"^\.attneave-tmp-([0-9]+)-(?:(h[0-9a-f]{8})-)?")


def _host_tag():
    import zlib

    # a directory on a shared (NFS) disk may hold the temporaries of runs on other machines,
    # whose pids mean nothing here. os.uname and crc32, not socket and hashlib: every command
    # that writes calls this, and those two imports cost ~10 ms of its start-up.
    host = os.uname().nodename if hasattr(os, "uname") else os.environ.get("COMPUTERNAME", "")
    return f"h{zlib.crc32(host.encode('utf-8', 'replace')):08x}"


_HOST = _host_tag()


def temp_prefix():
    """The beginning of the name of every temporary this process makes.

    Examples
    --------
    >>> temp_prefix().startswith(f".attneave-tmp-{os.getpid()}-h")
    True
    """
    return f"{TEMP_PREFIX}{os.getpid()}-{_HOST}-"


def _alive(pid):
    """True when a process `pid` exists (or may: one we may not signal is alive)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True
    return True


def is_stale_temporary(name):
    """True for a temporary of a process of this machine that is no longer running.

    Names of the older form (``.attneave-tmp-<pid>-<random>-``, no host)
    count as this machine's.

    Examples
    --------
    >>> is_stale_temporary(f".attneave-tmp-{os.getpid()}-k3j_x9a1-a.png"), is_stale_temporary("a.png")
    (False, False)
    """
    m = _OWNER_RE.match(name)
    if not m or not is_temporary(name) or (m.group(2) and m.group(2) != _HOST):
        return False
    return not _alive(int(m.group(1)))


_SWEPT = set()  # directories this process has already cleaned


def remove_stale_temporaries(directory, again=False):
    """Delete the temporaries that killed runs left in `directory` (not in its subdirectories).

    A run stopped by ``kill -9``, a power cut or a signal that came during
    its own cleanup leaves ``.attneave-tmp-<pid>-...`` files or directories;
    the next run that writes in the same place removes those whose process
    is gone (:func:`is_stale_temporary`); a live run's are left alone. Each
    directory is swept once per process unless `again`.

    Returns
    -------
    list of str
        The names removed.
    """
    import shutil

    directory = Path(directory)
    key = os.path.realpath(directory)
    if key in _SWEPT and not again:
        return []
    _SWEPT.add(key)
    removed = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for entry in entries:
        if not is_stale_temporary(entry.name):
            continue
        with contextlib.suppress(OSError):
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
            removed.append(entry.name)
    return removed


def is_temporary(name):
    """True for the name of a temporary file made by :func:`atomic_write`.

    Examples
    --------
    >>> is_temporary(".attneave-tmp-4242-k3j_x9a1-a.png"), is_temporary(".a.png.tmp")
    (True, False)
    """
    return bool(_TEMP_RE.match(name))


__all__ += ["TEMP_PREFIX", "is_temporary", "temp_prefix", "is_stale_temporary", "remove_stale_temporaries"]


@contextlib.contextmanager
def atomic_write(path, mode="w", fsync=False, **kwargs):
    """Open a temporary file beside `path` and move it into place on success.

    The rename is atomic, so a killed process (even ``kill -9``) leaves either
    the old file or the complete new one under `path`, never a partial one.

    Parameters
    ----------
    path : str or Path
        Final file name. Its directory must exist.
    mode : {'w', 'wb'}
        Text or binary.
    fsync : bool
        Also flush the data to disk before the rename. Only a power cut needs
        this, and it costs milliseconds per file, so it is off by default and
        kept for the files that mark a batch complete.
    **kwargs
        Passed to :func:`open` (e.g. ``newline=''``).

    Yields
    ------
    file
        The open temporary file. On an exception it is removed and `path` is
        left untouched.

    Raises
    ------
    InputError
        `path` is a directory, or its directory is missing or not writable.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a directory; expected a file name to write")
    kind = _special_kind(path)
    if kind:
        # the rename would put a regular file in place of /dev/null or a FIFO (as root, of a device)
        raise InputError(f"{path}: is {kind}, not a regular file; expected a file name to write")
    remove_stale_temporaries(path.parent)
    try:
        fd, tmp = tempfile.mkstemp(prefix=temp_prefix(), suffix=f"-{path.name[:80]}", dir=path.parent)
    except OSError as exc:
        # a missing or read-only directory is the user's input, not a crash
        raise InputError(f"{path}: cannot write there ({exc.strerror or exc})") from None
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            if fsync:
                fh.flush()
                os.fsync(fh.fileno())
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


#: errno values that mean the disk (full, over quota, failing), not the input: exit status 1
DISK_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EIO)


def disk_error_exit(command, output, exc, note="the earlier file, if any, is untouched"):
    """Say in one line that writing `output` failed for the disk's sake, and return exit status 1.

    Any other `exc` is raised again: only a full, over-quota or failing disk
    is neither the input's fault (exit 2) nor a bug (a traceback).

    Parameters
    ----------
    command : str
        The command's name, e.g. ``'surprisal'``.
    output : str or Path
        What was being written.
    exc : OSError
    note : str
        What the user should know about the files (atomic writes leave none half-written).

    Returns
    -------
    int
        1.
    """
    if getattr(exc, "errno", None) not in DISK_ERRORS:
        raise exc
    where = f" ({exc.filename})" if exc.filename else ""
    print(f"attneave {command}: error: {output}: {exc.strerror}{where}; {note}", file=sys.stderr)
    return 1


__all__ += ["DISK_ERRORS", "disk_error_exit"]


def _read_umask():
    # os.umask can only be read by setting it; do it once, at import, not in threads
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _read_umask()


def _kind(mode):
    """What a file that is neither regular nor a directory is, for messages."""
    import stat

    return ("a FIFO (named pipe)" if stat.S_ISFIFO(mode) else "a character device" if stat.S_ISCHR(mode)
            else "a block device" if stat.S_ISBLK(mode) else "a socket" if stat.S_ISSOCK(mode)
            else "a special file")


def _special_kind(path):
    """:func:`_kind` of an existing `path` (links followed) that is not a regular file or directory, else ''."""
    import stat

    try:
        mode = path.stat().st_mode
    except OSError:  # missing (the usual case for an output), or unreachable: mkstemp will say
        return ""
    return "" if stat.S_ISREG(mode) or stat.S_ISDIR(mode) else _kind(mode)


def check_regular_file(path, what="a file", max_bytes=None):
    """Check that `path` is a regular file that may be read, before opening it.

    Opening a FIFO blocks until someone writes to it, and a device such as
    ``/dev/zero`` never ends: every reader of user-given paths calls this
    first (it follows symbolic links, so a link to a regular file is fine).

    Parameters
    ----------
    path : str or Path
        The file to read.
    what : str
        What the file should be, for messages (e.g. ``'a CSV click file'``).
    max_bytes : int, optional
        Largest size accepted; :data:`MAX_TEXT_BYTES` is the limit for text
        inputs. None: no limit.

    Returns
    -------
    Path
        `path` as a :class:`pathlib.Path`.

    Raises
    ------
    InputError
        One line naming the file: missing, a directory, a FIFO, device or
        socket, unreadable, or larger than `max_bytes`.

    Examples
    --------
    >>> check_regular_file("/dev/null", "a CSV file")
    Traceback (most recent call last):
    ...
    attneave.stimuli.errors.InputError: /dev/null: is a character device, not a regular file; expected a CSV file
    """
    import stat

    path = Path(path)
    try:
        st = path.stat()
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except OSError as exc:  # no permission on a parent, a name too long, a loop of links, ...
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    mode = st.st_mode
    if stat.S_ISDIR(mode):
        raise InputError(f"{path}: is a directory, expected {what}")
    if not stat.S_ISREG(mode):
        raise InputError(f"{path}: is {_kind(mode)}, not a regular file; expected {what}")
    if max_bytes is not None and st.st_size > max_bytes:
        raise InputError(f"{path}: {st.st_size / 1e6:,.0f} MB is larger than the limit of "
                         f"{max_bytes / 1e6:,.0f} MB for {what}")
    if not os.access(path, os.R_OK):
        raise InputError(f"{path}: cannot read (permission denied)")
    return path


def temporary_directory(out):
    """Make an empty directory beside `out` in which to build it, and return its path.

    Its name follows the temporaries' rule (``.attneave-tmp-<pid>-<random>-<name>``),
    so that no user file is ever taken for it; :func:`replace_directory` then
    puts it in place. The parent of `out` is created if needed.

    Raises
    ------
    InputError
        If the directory cannot be made (naming `out` and the reason).
    """
    out = Path(out)
    # the working directory cannot be renamed aside (EBUSY) and would vanish under the user
    check_output_spares_inputs(out, [])
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temporaries(out.parent)
        return Path(tempfile.mkdtemp(prefix=temp_prefix(), suffix=f"-{out.name[:80]}", dir=out.parent))
    except OSError as exc:
        raise InputError(f"{out}: cannot be created ({exc.strerror or exc})") from None


def replace_directory(tmp, out):
    """Rename the finished directory `tmp` to `out`, replacing an old `out`.

    The old directory is first renamed aside (and restored if the second
    rename fails), then removed, so that `out` is at every moment either the
    old or the new directory, never a mixture. `tmp` and `out` must be on
    the same file system.
    """
    import shutil

    tmp, out = Path(tmp), Path(out)
    if not out.exists():
        os.replace(tmp, out)
        return
    old = Path(tempfile.mkdtemp(prefix=f"{temp_prefix()}old-", dir=out.parent))
    os.rmdir(old)
    os.replace(out, old)
    try:
        os.replace(tmp, out)
    except BaseException:
        os.replace(old, out)
        raise
    shutil.rmtree(old, ignore_errors=True)


def _resolved(path):
    """`path` made absolute with its links followed, as far as it exists."""
    return Path(os.path.realpath(Path(path).expanduser()))


def check_output_spares_inputs(output, inputs, what="-o"):
    """Refuse an output that would overwrite or delete one of the command's inputs.

    A file output may not be an input file; a directory output (replaced
    whole by ``--force``) may not be an input, nor contain one, nor be the
    working directory or one of its parents.

    Parameters
    ----------
    output : str or Path
        The output file or directory.
    inputs : iterable of str or Path
        The input files and directories the command reads.
    what : str
        The option that named `output`, for the message.

    Raises
    ------
    InputError
        One line naming the output and the input it would destroy.

    Examples
    --------
    >>> check_output_spares_inputs("clicks.csv", ["clicks.csv"])
    Traceback (most recent call last):
    ...
    attneave.stimuli.errors.InputError: -o clicks.csv: is an input of this command (clicks.csv); choose another output
    """
    if str(output) == "":
        raise InputError(f"{what}: empty output path; name a file or directory")
    out = _resolved(output)
    for item in inputs:
        if item is None:
            continue
        src = _resolved(item)
        if src == out:
            raise InputError(f"{what} {output}: is an input of this command ({item}); choose another output")
        if out in src.parents:
            raise InputError(f"{what} {output}: holds an input of this command ({item}), which replacing it "
                             "would delete; choose another output")
    if out == _resolved(os.getcwd()) or out in _resolved(os.getcwd()).parents:
        raise InputError(f"{what} {output}: is the working directory or holds it; choose another output")


def make_output_dir(out, what="-o"):
    """Create the output directory `out` (and its parents) or raise one line saying why not.

    Raises
    ------
    InputError
        `out` is empty, exists and is not a directory, or cannot be created
        (a parent is a file, no permission, a read-only or virtual file system).
    """
    if str(out) == "":
        raise InputError(f"{what}: empty output path; name a directory")
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{what} {out}: exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{what} {out}: cannot be created ({exc.strerror or exc})") from None
    if not os.access(out, os.W_OK | os.X_OK):
        raise InputError(f"{what} {out}: no permission to write in it")
    return out


__all__ += ["check_output_spares_inputs", "make_output_dir"]
