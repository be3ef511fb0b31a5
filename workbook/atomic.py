"""Write files whole or not at all: into a temporary file beside the target, then rename.

The temporary name carries the process id (crankbook.workspace), so a run that was
killed half-way leaves nothing the next run does not remove.
"""
import os
from contextlib import contextmanager
from pathlib import Path

from crankbook.workspace import sweep, temporary_name


@contextmanager
def atomic_path(path):
    """Yield a temporary path next to ``path``; on success it replaces ``path``.

    On an exception nothing is left behind and an existing ``path`` is untouched.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    sweep(path.parent, path.name)
    temporary = temporary_name(path)
    try:
        yield str(temporary)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.unlink(temporary)
