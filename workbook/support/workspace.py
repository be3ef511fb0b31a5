"""Outputs written whole or not at all, one writer at a time, nothing left behind.

* :func:`lock` — one crankbook run at a time writes a given output; a second one
  gets one clear refusal.  A lock whose process is gone (a killed run) is taken
  over.
* :func:`staged_directory` — a directory output (a class pack, grading results) is
  built in a hidden sibling and renamed into place; an existing one is replaced
  only once the new one is complete.
* :func:`sweep` — what killed runs left (staging folders, ``.tmp`` files carrying
  their process id) is removed by the next run.
* :func:`temporary_directory` — a scratch folder in TMPDIR named with this process's
  id (copies of student workbooks, LibreOffice profiles); :func:`sweep_temporary`
  removes those of runs that are gone, after killing the spreadsheet process group
  such a run recorded there.
"""
import os
import re
import shutil
import signal
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path

from crankbook.errors import BuildCancelled, BuildOptionError

MARK = ".crankbook-"                  # hidden names crankbook creates carry it


def alive(pid):
    """True when a process ``pid`` exists (on this machine)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


def _pid_of(name):
    """The process id a hidden name ``.<target>.crankbook-<pid>…`` carries, or None."""
    if MARK not in name:
        return None
    tail = name.rsplit(MARK, 1)[1]
    digits = tail.split(".", 1)[0].split("-", 1)[0]
    return int(digits) if digits.isdigit() else None


def sweep(parent, target_name):
    """Remove what a killed run left beside ``target_name`` in ``parent``."""
    parent = Path(parent)
    if not parent.is_dir():
        return
    prefix = f".{target_name}{MARK}"
    for entry in parent.iterdir():
        if not entry.name.startswith(prefix) or entry.name.endswith(".lock"):
            continue
        pid = _pid_of(entry.name)
        if pid is None or pid == os.getpid() or alive(pid):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink(missing_ok=True)


_HELD = set()                          # outputs this process holds the lock of


@contextmanager
def lock(target):
    """Hold the lock of output ``target`` (a file or directory path) while writing it
    (re-entrant: a run holding it may take it again)."""
    target = Path(target)
    held = os.path.abspath(target)
    if held in _HELD:
        yield
        return
    parent = target.parent if str(target.parent) else Path(".")
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise BuildOptionError(f"{target}: cannot write there ({error.strerror})") from None
    path = parent / f".{target.name}{MARK}{os.getpid()}.lock"
    claim = parent / f".{target.name}.crankbook.lock"
    for _ in range(2):
        try:
            descriptor = os.open(claim, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            try:
                holder = int(claim.read_text().strip() or 0)
            except (OSError, ValueError):
                holder = 0
            if holder and alive(holder):
                raise BuildCancelled(f"{target}: another crankbook run (process {holder}) is "
                                     f"writing it; wait for it to finish") from None
            claim.unlink(missing_ok=True)             # a killed run's lock: take it over
            continue
        except OSError as error:
            raise BuildOptionError(f"{target}: cannot write there ({error.strerror})") from None
        with os.fdopen(descriptor, "w") as handle:
            handle.write(str(os.getpid()))
        break
    else:
        raise BuildCancelled(f"{target}: another crankbook run is writing it")
    _HELD.add(held)
    try:
        sweep(parent, target.name)
        yield
    finally:
        _HELD.discard(held)
        claim.unlink(missing_ok=True)
        path.unlink(missing_ok=True)


def check_directory(target, option="-o"):
    """An output directory path, or BuildOptionError naming it and the rule."""
    text = str(target)
    if not text.strip():
        raise BuildOptionError(f"{option} '': give an output directory")
    target = Path(target)
    if len(target.name.encode()) > 200 or len(text.encode()) > 3000:
        raise BuildOptionError(f"{option} {text[:60]}…: the path is too long (at most 200 bytes "
                               f"of folder name, 3000 of path)")
    return target


OUTPUT_MARKER = ".crankbook"            # inside a folder crankbook wrote: the command


def _inside(path, folder):
    return path == folder or folder in path.parents


def check_output_folder(target, command, protected=(), option="-o"):
    """Refuse, before any work, an output folder that a replacing command must not
    touch: the root, a mount point, the current directory or one of its parents; a
    folder that is, contains or (for ``protected`` entries marked so) lies inside an
    input — ``protected`` is ``(path, may_lie_inside)`` pairs; an existing folder
    without the marker of an earlier output of the same ``command`` (crankbook
    replaces only what it wrote).  Returns the checked path."""
    target = check_directory(target, option)
    where = Path(os.path.abspath(target))
    here = Path(os.path.abspath(Path.cwd()))
    if where == Path(where.anchor) or os.path.ismount(where) or _inside(here, where):
        raise BuildOptionError(f"{option} {target}: is the current folder, one of its parents "
                               f"or a mount point; give a folder of its own")
    for path, may_lie_inside in protected:
        if path is None:
            continue
        guarded = Path(os.path.abspath(path))
        if _inside(guarded, where) or (not may_lie_inside and _inside(where, guarded)):
            raise BuildOptionError(f"{option} {target}: would replace or write into {path}, "
                                   f"an input of this run; give another folder")
    if where.is_symlink():
        raise BuildOptionError(f"{option} {target}: is a link; give a folder of its own")
    if where.exists() and not where.is_dir():
        raise BuildOptionError(f"{option} {target}: is a file; give a folder")
    if where.is_dir() and any(where.iterdir()):
        marker = where / OUTPUT_MARKER
        try:
            written_by = marker.read_text(encoding="utf-8").strip() \
                if marker.is_file() and not marker.is_symlink() else None
        except (OSError, UnicodeDecodeError):
            written_by = None
        if written_by != command:
            raise BuildOptionError(f"{option} {target}: exists and was not written by "
                                   f"crankbook {command} (no {OUTPUT_MARKER} of it); give a new "
                                   f"folder, or empty this one yourself")
    return target


@contextmanager
def staged_directory(target, replace=False, command=None):
    """Yield a hidden directory beside ``target``; on success it becomes ``target``.

    ``replace``: an existing ``target`` is replaced (after the new one is complete) —
    only one that carries the marker of an earlier output of ``command`` (checked
    again here; callers check it before their work with :func:`check_output_folder`);
    otherwise an existing non-empty ``target`` is refused.  The new folder gets the
    marker and the user's umask (a scratch folder is private until renamed).
    """
    target = check_directory(target)
    if target.exists() and not target.is_dir():
        raise BuildOptionError(f"-o {target}: is a file; give a directory")
    if target.exists() and not replace and any(target.iterdir()):
        raise BuildOptionError(f"-o {target}: exists and is not empty; give a new directory")
    if replace:
        check_output_folder(target, command)
    with lock(target):
        parent = target.parent if str(target.parent) else Path(".")
        try:
            staging = Path(tempfile.mkdtemp(prefix=f".{target.name}{MARK}{os.getpid()}-",
                                            dir=parent))
        except OSError as error:
            raise BuildOptionError(f"-o {target}: cannot write there ({error.strerror})") \
                from None
        try:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(staging, 0o777 & ~umask)
            old = None
            try:
                if command:
                    (staging / OUTPUT_MARKER).write_text(command + "\n", encoding="utf-8")
                yield staging
                if target.exists():
                    old = parent / f".{target.name}{MARK}{os.getpid()}-old"
                    os.replace(target, old)
                os.replace(staging, target)
            except OSError as error:       # a full disk mid-way: one line, the old folder whole
                if old is not None and old.exists() and not target.exists():
                    os.replace(old, target)
                raise BuildOptionError(f"-o {target}: cannot write there "
                                       f"({error.strerror or type(error).__name__}); the "
                                       f"folder is as it was") from None
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        finally:
            if staging.exists():
                shutil.rmtree(staging, ignore_errors=True)


def temporary_name(path):
    """A hidden temporary name beside ``path`` that carries this process's id."""
    path = Path(path)
    return path.parent / f".{path.name}{MARK}{os.getpid()}.tmp"


ENGINE_GROUP = "engine.pgid"          # a scratch folder's record of its engine process group
SCRATCH = re.compile(r"crankbook-[a-z]+-(\d+)-")
RECORD_BYTES = 32                     # a process group id: anything longer is not ours


def _private(folder):
    """True when ``folder`` is a real directory of this user that no one else can
    enter (mode 0700 or stricter)."""
    try:
        info = os.lstat(folder)
    except OSError:
        return False
    return stat.S_ISDIR(info.st_mode) and info.st_uid == os.getuid() and \
        not info.st_mode & 0o077


def scratch_root():
    """This user's private folder for crankbook's scratch folders, in TMPDIR:
    ``crankbook-<uid>`` with mode 0700.  Another user cannot plant anything in it;
    one that was planted under its name (another owner, a link, open to others) is
    never used — the run then takes a fresh private folder of its own."""
    base = Path(tempfile.gettempdir())
    root = base / f"crankbook-{os.getuid()}"
    try:
        root.mkdir(mode=0o700)
    except FileExistsError:
        pass
    except OSError:
        return Path(tempfile.mkdtemp(prefix=f"crankbook-{os.getuid()}-", dir=base))
    if not _private(root):
        return Path(tempfile.mkdtemp(prefix=f"crankbook-{os.getuid()}-", dir=base))
    return root


def temporary_directory(kind, directory=None):
    """A scratch folder ``crankbook-<kind>-<pid>-…`` (in this user's private
    :func:`scratch_root` unless ``directory`` is given) removed when the block ends
    (and by the next run's :func:`sweep_temporary` when this process is killed first)."""
    return tempfile.TemporaryDirectory(prefix=f"crankbook-{kind}-{os.getpid()}-",
                                       dir=directory or scratch_root())


def record_engine(folder, process_group):
    """Note in scratch ``folder`` the process group of the engine working in it."""
    try:
        (Path(folder) / ENGINE_GROUP).write_text(str(process_group))
    except OSError:
        pass


def _recorded_group(record):
    """The process group a record names, read without following a link, blocking on a
    pipe or reading more than a few bytes; None for anything else."""
    try:
        descriptor = os.open(record, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0)
                             | getattr(os, "O_NONBLOCK", 0))
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):
            return None
        text = os.read(descriptor, RECORD_BYTES + 1)
    except OSError:
        return None
    finally:
        os.close(descriptor)
    text = text.decode("ascii", "replace").strip()
    return int(text) if len(text) <= RECORD_BYTES and text.isdigit() and int(text) > 1 else None


def _our_engine(group, folder):
    """True when process group ``group`` is alive and every process in it is this
    user's and was started on scratch ``folder`` (its path is in the command line, as
    LibreOffice's profile and Gnumeric's files are): a stale or planted record never
    names someone else's processes.  Without /proc (not Linux) nothing is known, so
    nothing is signalled."""
    proc, members = Path("/proc"), 0
    if not proc.is_dir():
        return False
    for entry in proc.iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            if int(fields[2]) != group:
                continue
            if entry.stat().st_uid != os.getuid():
                return False
            command = (entry / "cmdline").read_bytes().replace(b"\0", b" ")
        except (OSError, ValueError, IndexError):
            continue
        members += 1
        if str(folder).encode() not in command:
            return False
    return members > 0


def sweep_temporary(directory=None):
    """Remove the scratch folders of crankbook runs that are gone — killing first any
    spreadsheet engine they left running, when it is provably theirs — and return how
    many were removed.  Only this user's own folders of the private scratch root are
    touched."""
    removed = 0
    root = Path(directory or scratch_root())
    try:
        entries = list(root.iterdir())
    except OSError:
        return 0
    for entry in entries:
        match = SCRATCH.match(entry.name)
        if not match or not _private(entry):
            continue
        pid = int(match.group(1))
        if pid == os.getpid() or alive(pid):
            continue
        record = entry / ENGINE_GROUP
        group = _recorded_group(record)
        if group is not None and _our_engine(group, entry):
            try:
                os.killpg(group, signal.SIGKILL)
            except OSError:
                pass
        shutil.rmtree(entry, ignore_errors=True)
        removed += 1
    return removed
