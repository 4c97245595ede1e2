"""The one atomic writer of murus: output folders, single output files and the pieces of
studies (:func:`atomic_write` is the one low-level writer; everything else calls it).

Rules (README "Outputs"):

* A command never deletes what it did not write. An output folder holds a small manifest,
  ``.murus-manifest.json`` (command, UTC time, relative paths written); a re-run replaces
  exactly the files listed there, removes the listed files the new run no longer writes, and
  leaves every other file alone. A new output whose name collides with a file murus did not
  write is an :class:`OutputError` naming the file, raised before anything is moved (and,
  when the command knows its file names, before anything is computed).
* New results become visible atomically and durably: every file is flushed to the disk
  (``fsync``) before it is renamed into place, and its folder after. A folder that does not
  exist yet is built as a hidden temporary sibling and renamed into place; into an existing
  folder each file is moved with :func:`os.replace` (each file atomic), the manifest last.
  If a move fails, the files already moved are put back, so the folder is as it was; Ctrl-C
  is held off during the moves (they take milliseconds) and raised right after.
* Before any computation, :func:`check_dir` / :func:`check_file` refuse an ``--out`` that
  names an existing file (folder outputs) or folder (file outputs), lies under a file, is
  ``.`` or the current working folder, or whose nearest existing ancestor is not a writable
  folder. Missing parent folders are created (``murus demo`` writes ``out/demo`` in a fresh
  clone), but only at the end, when the results are written, and only below a writable
  folder; on failure the parents created are removed again.
* Folders get the permissions of the user's umask (``0o777 & ~umask``), files
  ``0o666 & ~umask``.
* On any failure, including KeyboardInterrupt, the temporary folder or file is removed and
  the destination is left as it was.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

from murus.errors import MurusError

MANIFEST = ".murus-manifest.json"
"""Name of the manifest file in an output folder."""

_FORMAT = "murus-manifest/1"

FILES = ".murus-files.json"
"""Name of the list of single output files murus wrote in a folder (:func:`write_file` with
``record=True``)."""

#: First bytes of the text files murus writes (motion records, VALIDATION.md): such a file is
#: murus's own and may be replaced.
_SIGNATURES = (b"# murus",)


def _recorded(folder: Path) -> set[str]:
    try:
        data = json.loads((folder / FILES).read_text(encoding="utf-8"))
        return {str(x) for x in data.get("files", [])}
    except (OSError, ValueError, AttributeError):
        return set()


def owned_file(p) -> bool:
    """True when the existing file ``p`` was written by murus: listed in its folder's
    :data:`FILES` or manifest, starting with a murus signature (``# murus``), or lying in a
    study folder of murus (``study.json`` beside it)."""
    p = Path(p)
    folder = p.parent if str(p.parent) else Path(".")
    if p.name in _recorded(folder) or p.name in read_manifest(folder):
        return True
    try:
        with open(p, "rb") as f:
            head = f.read(64)
    except OSError:
        return False
    return head.startswith(_SIGNATURES) or (folder / "study.json").is_file()


def _record(out: Path) -> None:
    """Add ``out`` to the :data:`FILES` list of its folder (atomically)."""
    folder = out.parent if str(out.parent) else Path(".")
    names = sorted(_recorded(folder) | {out.name})
    text = json.dumps({"format": "murus-files/1", "files": names}, indent=2) + "\n"
    atomic_write(folder / FILES, lambda p: Path(p).write_text(text, encoding="utf-8"))


class OutputError(MurusError, ValueError):
    """A bad output path: the message is one line naming the offending path."""


def umask() -> int:
    """The process umask (read without changing it for longer than one call)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def dir_mode() -> int:
    """Permission bits of a new folder under the current umask (``0o777 & ~umask``)."""
    return 0o777 & ~umask()


def file_mode() -> int:
    """Permission bits of a new file under the current umask (``0o666 & ~umask``)."""
    return 0o666 & ~umask()


# ------------------------------------------------------------------------------ checks
def _is_cwd(p: Path) -> bool:
    try:
        return p.resolve() == Path.cwd().resolve()
    except OSError:
        return False


def _writable_ancestor(p: Path, label: str) -> None:
    """Check that the nearest existing ancestor of ``p`` is a writable folder."""
    anc = p.parent if str(p.parent) != "" else Path(".")
    while not anc.exists() and not anc.is_symlink():
        if anc == anc.parent:
            break
        anc = anc.parent
    if anc.exists() and not anc.is_dir():
        raise OutputError(f"{label} {p}: {anc} is a file, not a folder")
    if anc.is_symlink() and not anc.exists():
        raise OutputError(f"{label} {p}: {anc} is a broken link")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise OutputError(f"{label} {p}: folder {anc} is not writable")


def read_manifest(folder: Path) -> list[str]:
    """Relative paths listed in ``folder``'s manifest (empty when there is none).

    Raises :class:`OutputError` when a file of that name exists but is not a murus
    manifest (it is then a user's file, which murus will not overwrite)."""
    path = Path(folder) / MANIFEST
    if not path.exists():
        return []
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("format") != _FORMAT:
            raise ValueError
        files = [str(f) for f in data["files"]]
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        raise OutputError(f"{path}: not a murus manifest; murus will not overwrite it "
                          "(move it away or choose another --out)") from None
    return [f for f in files if _safe_rel(f)]


def _safe_rel(rel: str) -> bool:
    p = Path(rel)
    return not p.is_absolute() and ".." not in p.parts and rel not in ("", ".", MANIFEST)


def _collisions(folder: Path, names: Iterable[str], listed: set[str]) -> None:
    for rel in names:
        parts = Path(rel).parts
        for i in range(1, len(parts)):
            sub = folder.joinpath(*parts[:i])
            if sub.exists() and not sub.is_dir():
                raise OutputError(f"{sub}: a file murus did not write is in the way of "
                                  f"{folder / rel}; move it away or choose another --out")
        dest = folder / rel
        if dest.is_dir() and not dest.is_symlink():
            raise OutputError(f"{dest}: a folder is in the way of an output file; move it "
                              "away or choose another --out")
        if (dest.exists() or dest.is_symlink()) and rel not in listed:
            raise OutputError(f"{dest}: exists and was not written by murus; move it away or "
                              "choose another --out")


def check_dir(out, names: Iterable[str] | None = None, label: str = "--out") -> Path:
    """Check an output folder before any computation; the file system is not touched.

    Parameters
    ----------
    out : path-like
        Output folder (it may exist; missing parents are created when writing).
    names : iterable of str, optional
        Relative paths the command will write, when known up front: a name that exists in
        ``out`` and is not in its manifest is refused now, before anything is computed.
    label : str
        How the path is named in messages (the option, ``--out``).

    Returns
    -------
    Path
        ``out`` as a Path.

    Raises
    ------
    OutputError
        ``out`` is empty, ``.`` or the current folder, the root of the file system, an
        existing file, lies under a file,
        its nearest existing ancestor is not a writable folder, or a known output name
        collides with a file murus did not write.
    """
    p = Path(out)
    if str(out).strip() == "":
        raise OutputError(f"{label}: empty path")
    if _is_cwd(p):
        raise OutputError(f"{label} {out}: is the current folder; name a sub-folder "
                          "(e.g. --out out)")
    if p.resolve().parent == p.resolve():
        raise OutputError(f"{label} {out}: is the root of the file system; name a sub-folder "
                          "(e.g. --out out)")
    if p.exists() or p.is_symlink():
        if not p.is_dir():
            raise OutputError(f"{label} {out}: exists and is not a folder")
        if not os.access(p, os.W_OK | os.X_OK):
            raise OutputError(f"{label} {out}: folder is not writable")
        if names is not None:
            _collisions(p, names, set(read_manifest(p)))
        else:
            read_manifest(p)
    _writable_ancestor(p, label)
    return p


def check_file(out, suffixes: Iterable[str], label: str = "--out") -> Path:
    """Check an output file before any computation; the file system is not touched.

    An existing file at ``out`` is replaced only when murus wrote it (:func:`owned_file`);
    any other existing file, an existing folder and an extension the command cannot write are
    refused.

    Parameters
    ----------
    out : path-like
        Output file.
    suffixes : iterable of str
        Extensions the command can write, e.g. ``(".csv", ".at2")`` (case-insensitive).
    label : str
        How the path is named in messages.

    Returns
    -------
    Path

    Raises
    ------
    OutputError
    """
    p = Path(out)
    allowed = [s.lower() for s in suffixes]
    if str(out).strip() == "":
        raise OutputError(f"{label}: empty path")
    if p.is_dir():
        raise OutputError(f"{label} {out}: is a folder; name a file ({' or '.join(allowed)})")
    if p.suffix.lower() not in allowed:
        what = f"extension {p.suffix}" if p.suffix else "no extension"
        raise OutputError(f"{label} {out}: {what}; this command writes "
                          f"{' or '.join(allowed)}")
    if p.is_file() and not owned_file(p):
        raise OutputError(f"{label} {out}: exists and was not written by murus; remove it or "
                          "name another file")
    if p.exists() and not os.access(p.parent if str(p.parent) else Path("."), os.W_OK):
        raise OutputError(f"{label} {out}: folder {p.parent} is not writable")
    _writable_ancestor(p, label)
    return p


# ------------------------------------------------------------------------------ helpers
def _make_parents(folder: Path) -> list[Path]:
    """Create the missing ancestors of ``folder`` (umask permissions); return them,
    deepest last."""
    missing = []
    anc = folder.parent
    while not anc.exists() and anc != anc.parent:
        missing.append(anc)
        anc = anc.parent
    created = []
    for d in reversed(missing):
        d.mkdir()
        created.append(d)
    return created


def _remove_created(created: list[Path]) -> None:
    for d in reversed(created):
        with contextlib.suppress(OSError):
            d.rmdir()


def _times(paths: Iterable[Path]) -> dict[Path, tuple[int, int]]:
    """Access and modification times of existing folders (restored after a failure, so that
    a failed command leaves even the folders' times as they were)."""
    out = {}
    for p in paths:
        with contextlib.suppress(OSError):
            st = os.stat(p)
            out[p] = (st.st_atime_ns, st.st_mtime_ns)
    return out


def _restore_times(times: dict[Path, tuple[int, int]]) -> None:
    for p, ns in times.items():
        with contextlib.suppress(OSError):
            os.utime(p, ns=ns)


def _nearest_existing(p: Path) -> Path:
    anc = p.parent if str(p.parent) else Path(".")
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    return anc


def _chmod_tree(root: Path) -> None:
    dm, fm = dir_mode(), file_mode()
    os.chmod(root, dm)
    for base, dirs, files in os.walk(root):
        for d in dirs:
            os.chmod(os.path.join(base, d), dm)
        for f in files:
            p = os.path.join(base, f)
            if not os.path.islink(p):
                os.chmod(p, fm)


def _files(root: Path) -> list[str]:
    out = []
    for base, dirs, files in os.walk(root):
        dirs.sort()
        for f in sorted(files):
            out.append(Path(base, f).relative_to(root).as_posix())
    return [f for f in out if f != MANIFEST]


def _manifest_text(command: str, files: list[str]) -> str:
    return json.dumps({"format": _FORMAT, "command": command,
                       "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                       "files": sorted(files)}, indent=2) + "\n"


def write_text(path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (temporary sibling, then :func:`os.replace`),
    with umask permissions; missing parents are created. Returns the path."""
    path = Path(path)
    return write_file(path, lambda tmp: Path(tmp).write_text(text, encoding=encoding,
                                                            newline="\n"))


@contextlib.contextmanager
def _hold_sigint() -> Iterator[None]:
    """Defer Ctrl-C during a short critical section (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got = []

    def handler(signum, frame):
        got.append(signum)

    try:
        old = signal.signal(signal.SIGINT, handler)
    except ValueError:  # pragma: no cover - not the main interpreter
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
    if got:
        raise KeyboardInterrupt


# ------------------------------------------------------------------------------ writers
def _fsync_path(path, directory: bool = False) -> None:
    """Flush ``path`` (a file, or with ``directory`` a folder's entries) to the disk.

    Folders are flushed on POSIX systems only (Windows cannot open a folder for it), and a
    file system that cannot flush a folder (``EINVAL``) is let be."""
    if directory and os.name == "nt":  # pragma: no cover - Windows
        return
    try:
        fd = os.open(path, os.O_RDONLY if directory else os.O_RDWR)
    except OSError:
        if directory:
            return
        fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


def process_tmp_name(path) -> str:
    """Temporary name ``.NAME.tmp-PID`` of a piece of a study written by this process (see
    :func:`atomic_write`): one per process and piece, recognisable in a study folder."""
    return f".{Path(path).name}.tmp-{os.getpid()}"


def atomic_write(path, write: Callable[[Path], object], *, tmp_name: str | None = None,
                 fsync: bool = True, on_replace: Callable[[], object] | None = None) -> Path:
    """Write one file atomically: the one low-level writer of murus.

    ``write(tmp)`` writes the content to a temporary sibling ``tmp`` of ``path`` (same
    folder, so that the rename is atomic); the file gets the umask permissions
    (:func:`file_mode`), is flushed to the disk (``fsync``), and is renamed over ``path`` with
    :func:`os.replace`; then the folder entry is flushed too. A reader sees the old file or
    the new one, never a partial one, even after a power cut. On any failure (including
    Ctrl-C) the temporary file is removed and ``path`` is as it was. Ctrl-C is held off
    during the rename (and ``on_replace``) and raised right after.

    :func:`write_file` (output files of the CLI: missing parents, ownership record, one-line
    :class:`OutputError`), the manifest and the pieces of studies
    (:mod:`murus.studies.sweep`, :mod:`murus.retaining.study`) all write through it.

    Parameters
    ----------
    path : path-like
        Destination file; its folder must exist.
    write : callable
        ``write(tmp)`` writes the whole content to the path ``tmp``.
    tmp_name : str, optional
        File name of the temporary sibling. Default: a fresh unique name
        (:func:`tempfile.mkstemp`, ``.NAME.XXXXXXXX.EXT``, ending in the extension of
        ``path`` so that writers picking the format from it work). The pieces of studies
        (checksummed chunks and cases, ``study.json``, ``result.nc``) pass their own name,
        :func:`process_tmp_name` (``.NAME.tmp-PID``, as they always had): one per process and
        piece, so that the workers writing into one study folder never share one.
    fsync : bool
        Flush the file and the folder to the disk (default). Only files that are rewritten
        every second and have no value after a crash (progress files) pass False.
    on_replace : callable, optional
        Called right after the rename, inside the same Ctrl-C-deferred section (e.g. to
        record the file as murus's own).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    OSError
        The folder is missing or not writable, or ``write`` failed (nothing changed).
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    tmp: Path | None = None
    try:
        if tmp_name is None:
            fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix or ".tmp",
                                        dir=folder)
            os.close(fd)
            tmp = Path(name)
        else:
            tmp = folder / tmp_name
        write(tmp)
        os.chmod(tmp, file_mode())
        if fsync:
            _fsync_path(tmp)
        with _hold_sigint():
            os.replace(tmp, path)
            tmp = None
            if fsync:
                _fsync_path(folder, directory=True)
            if on_replace is not None:
                on_replace()
    except BaseException:
        if tmp is not None:
            with contextlib.suppress(OSError):
                tmp.unlink()
        raise
    return path


def write_file(out, write: Callable[[Path], object], record: bool = False) -> Path:
    """Write one output file atomically.

    ``write(tmp)`` writes a temporary file in the same folder as ``out`` (its name ends with
    the same extension, so writers that pick the format from it work); it is then given the
    umask permissions, flushed to the disk and renamed over ``out`` (:func:`atomic_write`).
    Missing parents are created (and removed again on failure). On any failure nothing
    changes at ``out``.

    Parameters
    ----------
    out : path-like
        Destination file.
    write : callable
        ``write(path)`` writes the content to ``path``.
    record : bool
        Add ``out`` to the :data:`FILES` list of its folder, so that a later run may replace
        it (:func:`check_file`); for outputs that carry no murus signature.

    Returns
    -------
    Path
        ``out``.
    """
    out = Path(out)
    times = _times([_nearest_existing(out)])
    try:
        created = _make_parents(out)
    except OSError as exc:
        raise OutputError(f"{out}: cannot create its folder ({exc.strerror or exc})") from None
    started = []

    def _write(tmp):
        started.append(tmp)
        return write(tmp)

    try:
        try:
            atomic_write(out, _write, on_replace=(lambda: _record(out)) if record else None)
        except OSError as exc:
            if started:  # raised by ``write`` or the rename: as it is
                raise
            raise OutputError(f"{out}: cannot write there ({exc.strerror or exc})") from None
    except BaseException:
        _remove_created(created)
        _restore_times(times)
        raise
    return out


def write_dir(out, write: Callable[[Path], object], command: str = "murus",
              names: Iterable[str] | None = None) -> Path:
    """Build an output folder with ``write(tmp)`` and publish it under the rules of this
    module (see the module docstring).

    Parameters
    ----------
    out : path-like
        Output folder; it may exist (only files of its manifest are replaced).
    write : callable
        ``write(tmp)`` writes the outputs into the empty temporary folder ``tmp``.
    command : str
        The command line recorded in the manifest.
    names : iterable of str, optional
        The relative paths that will be written, when known: checked before ``write`` runs.

    Returns
    -------
    Path
        ``out``.

    Raises
    ------
    OutputError
        See :func:`check_dir`; also raised after ``write`` when a written name collides with
        a file murus did not write (nothing is moved then).
    """
    with staged_dir(out, command, names) as tmp:
        write(tmp)
    return Path(out)


@contextlib.contextmanager
def staged_dir(out, command: str = "murus", names: Iterable[str] | None = None):
    """Context manager form of :func:`write_dir`: yields the empty temporary folder; its
    files are published into ``out`` when the block ends without an exception, and it is
    removed in every case."""
    out = check_dir(out, names)
    exists = out.is_dir()
    times = _times([out if exists else _nearest_existing(out)])
    created = []
    try:
        created = [] if exists else _make_parents(out)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.murus-",
                                    dir=out if exists else out.parent))
    except BaseException as exc:
        _remove_created(created)
        _restore_times(times)
        if isinstance(exc, OSError):
            raise OutputError(f"{out}: cannot write there ({exc.strerror or exc})") from None
        raise
    try:
        yield tmp
        files = _files(tmp)
        try:
            for rel in files:  # the new files reach the disk before they become visible
                if not (tmp / rel).is_symlink():
                    _fsync_path(tmp / rel)
            if exists:
                _publish_into(tmp, out, files, command)
                for d in sorted({(out / rel).parent for rel in files}):
                    _fsync_path(d, directory=True)
            else:
                _chmod_tree(tmp)
                (tmp / MANIFEST).write_text(_manifest_text(command, files), encoding="utf-8")
                os.chmod(tmp / MANIFEST, file_mode())
                _fsync_path(tmp / MANIFEST)
                for d in sorted({(tmp / rel).parent for rel in files} | {tmp}):
                    _fsync_path(d, directory=True)
                with _hold_sigint():
                    os.rename(tmp, out)
                _fsync_path(out.parent, directory=True)
        except OSError as exc:
            raise OutputError(f"{out}: cannot write the outputs ({exc.strerror or exc})") \
                from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        _remove_created(created)
        if not out.exists() or exists:
            _restore_times(times)
        raise
    shutil.rmtree(tmp, ignore_errors=True)


def _publish_into(tmp: Path, out: Path, files: list[str], command: str) -> None:
    """Move the files of ``tmp`` (a hidden sub-folder of ``out``) into ``out``."""
    listed = read_manifest(out)
    _collisions(out, files, set(listed))
    stale = [f for f in listed if f not in set(files)
             and (out / f).is_file() and not (out / f).is_symlink()]
    root = out.resolve()  # never follow a link out of ``out`` to remove a file
    stale = [f for f in stale if (out / f).resolve().parent.is_relative_to(root)
             and (out / f).parent.resolve() == (out / f).resolve().parent]
    dm, fm = dir_mode(), file_mode()
    backup = tmp / ".old"
    done: list[tuple[str, bool]] = []  # (relative path, had an old version)
    made: list[Path] = []
    removed: list[str] = []
    manifest = out / MANIFEST
    manifest_old = backup / MANIFEST if manifest.exists() else None
    touched = {out} | {out / a for rel in [*files, *stale] for a in Path(rel).parents[:-1]}
    times = _times(sorted(touched))
    with _hold_sigint():
        try:
            backup.mkdir()
            if manifest_old is not None:  # a hard link keeps the old file (inode, times)
                try:
                    os.link(manifest, manifest_old)
                except OSError:
                    shutil.copy2(manifest, manifest_old)
            # a manifest covering old and new files first, so that an interrupted move
            # (power cut) still lists everything murus may have written
            _replace_text(out, MANIFEST, _manifest_text(command, sorted(set(listed) | set(files))),
                          tmp)
            for rel in files:
                dest = out / rel
                for anc in reversed(Path(rel).parents[:-1]):
                    d = out / anc
                    if not d.exists():
                        d.mkdir()
                        os.chmod(d, dm)
                        made.append(d)
                src = tmp / rel
                os.chmod(src, fm)
                had = dest.exists()
                if had:
                    keep = backup / rel
                    keep.parent.mkdir(parents=True, exist_ok=True)
                    os.replace(dest, keep)
                done.append((rel, had))
                os.replace(src, dest)
            for rel in stale:
                keep = backup / rel
                keep.parent.mkdir(parents=True, exist_ok=True)
                os.replace(out / rel, keep)
                removed.append(rel)
            _replace_text(out, MANIFEST, _manifest_text(command, files), tmp)
        except BaseException:
            for rel in removed:
                with contextlib.suppress(OSError):
                    os.replace(backup / rel, out / rel)
            for rel, had in reversed(done):
                with contextlib.suppress(OSError):
                    if had:
                        os.replace(backup / rel, out / rel)
                    else:
                        (out / rel).unlink()
            for d in reversed(made):
                with contextlib.suppress(OSError):
                    d.rmdir()
            with contextlib.suppress(OSError):
                if manifest_old is None:
                    manifest.unlink()
                else:
                    os.replace(manifest_old, manifest)
            _restore_times(times)
            raise
    # stale files removed: drop the folders murus emptied (never a folder with other files)
    for rel in removed:
        for anc in Path(rel).parents[:-1]:
            with contextlib.suppress(OSError):
                (out / anc).rmdir()


def _replace_bytes(out: Path, rel: str, data: bytes, tmp: Path) -> None:
    """Replace ``out / rel`` with ``data`` atomically (``tmp``, the staging folder, is not
    used any more: the temporary file is a sibling of the destination)."""
    atomic_write(out / rel, lambda p: Path(p).write_bytes(data))


def _replace_text(out: Path, rel: str, text: str, tmp: Path) -> None:
    _replace_bytes(out, rel, text.encode("utf-8"), tmp)


_command: list[str] | None = None


def set_command(args) -> None:
    """Record the arguments of the running ``murus`` command (set by the CLI entry point)."""
    global _command
    _command = [str(a) for a in args]


def command_line() -> str:
    """The command recorded in a manifest: ``murus`` and the arguments given (as set by the
    CLI entry point; else this process's arguments when it is the ``murus`` program)."""
    import shlex
    import sys

    if _command is not None:
        return shlex.join(["murus", *_command])
    if sys.argv and os.path.basename(sys.argv[0]).removesuffix(".exe") == "murus":
        return shlex.join(["murus", *sys.argv[1:]])
    return "murus"


def add_to_folder(folder, rel: str, text: str) -> Path:
    """Write one more file, ``folder/rel`` (text), into an existing output folder, atomically,
    and record it as murus's own: added to the folder's manifest (its command and time kept),
    or to its :data:`FILES` list when the folder has no manifest (a study folder). A file of
    that name that murus did not write is an :class:`OutputError` (nothing written).

    Parameters
    ----------
    folder : path-like
        An existing output folder.
    rel : str
        File name inside ``folder``.
    text : str
        Content (written as UTF-8).

    Returns
    -------
    Path
        ``folder / rel``.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise OutputError(f"{folder}: not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{folder}: folder is not writable")
    out = folder / rel
    if out.is_dir():
        raise OutputError(f"{out}: a folder is in the way; move it away")
    listed = read_manifest(folder)
    if (out.exists() or out.is_symlink()) and rel not in listed and rel not in \
            _recorded(folder):
        raise OutputError(f"{out}: exists and was not written by murus; move it away")
    data = text.encode("utf-8")
    if (folder / MANIFEST).exists():
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))

        def _update() -> None:
            if rel not in listed:
                manifest["files"] = sorted({*listed, rel})
                blob = json.dumps(manifest, indent=2) + "\n"
                atomic_write(folder / MANIFEST, lambda p: Path(p).write_text(
                    blob, encoding="utf-8"))

        atomic_write(out, lambda p: Path(p).write_bytes(data), on_replace=_update)
    else:
        atomic_write(out, lambda p: Path(p).write_bytes(data), on_replace=lambda: _record(out))
    return out
