"""Why a path the user named cannot be read as a file, in words."""
import os
import stat
from pathlib import Path


def not_a_file(path):
    """None when ``path`` is a regular file (or a link to one); else why not: missing,
    a folder, or a pipe, device or socket — which reading would block on, or read
    without end."""
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return "no such file"
    except OSError as error:
        return f"cannot be opened ({error.strerror})"
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a folder, not a file"
    kind = ("a named pipe (FIFO)" if stat.S_ISFIFO(mode) else
            "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else
            "a socket" if stat.S_ISSOCK(mode) else "not a file")
    return f"{kind}, not a regular file"


def require_file(path, error, what=""):
    """Raise ``error`` ("<what> <path>: <why>") unless ``path`` is a regular file."""
    reason = not_a_file(path)
    if reason:
        raise error(f"{what} {path}: {reason}".lstrip())
