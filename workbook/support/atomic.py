"""Write files whole or not at all: into a temporary file beside the target, then rename.

The temporary name carries the process id (crankbook.support.workspace), so a run that was
killed half-way leaves nothing the next run does not remove.
"""
import os
from contextlib import contextmanager
from pathlib import Path

from xlsxwriter.exceptions import FileCreateError

from crankbook.errors import OutputPathError
from crankbook.support.workspace import lock, sweep, temporary_name


def _cannot_write(path, error):
    reason = getattr(error, "strerror", None) or str(error).split("] ", 1)[-1].split(": '")[0]
    shown = str(path) if len(str(path)) <= 120 else str(path)[:60] + "…" + str(path)[-40:]
    return OutputPathError(f"{shown}: cannot write there ({reason})")


@contextmanager
def atomic_path(path):
    """Yield a temporary path next to ``path``; on success it replaces ``path``.

    On an exception nothing is left behind and an existing ``path`` is untouched.
    """
    path = Path(path)
    temporary = temporary_name(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        sweep(path.parent, path.name)
    except OSError as error:
        raise _cannot_write(path, error) from None
    with lock(path):                      # a second run into the same file is refused
        yield from _written(path, temporary)


def _written(path, temporary):
    try:
        try:
            yield str(temporary)
        except (OSError, FileCreateError) as error:
            raise _cannot_write(path, error) from None
        try:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)
            os.replace(temporary, path)
        except OSError as error:
            raise _cannot_write(path, error) from None
    finally:
        try:
            if os.path.exists(temporary):
                os.unlink(temporary)
        except OSError:
            pass
