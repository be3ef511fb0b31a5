"""Progress on a terminal, silence elsewhere: what is being done, n of N, elapsed.

Every command that can take more than a couple of seconds reports through here, with
tqdm: on a terminal (stderr) unless ``--quiet``; never in a pipe, a log or a test. The
API functions take ``progress=`` (True, False, or None for "on a terminal").
"""
import shutil
import sys
import threading
from contextlib import contextmanager

from tqdm import tqdm


def shown(progress=None):
    """Whether to show progress: ``progress`` when given, else when stderr is a terminal."""
    if progress is not None:
        return bool(progress)
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _screen():
    """The terminal's width and height, 80 × 24 where it reports 0 (a pseudo-terminal
    nobody sized, as under ``script`` or an IDE: tqdm would draw nothing there)."""
    size = shutil.get_terminal_size((80, 24))
    return {"ncols": size.columns or 80, "nrows": size.lines or 24}


def steps(iterable, what, total=None, progress=None, unit="file"):
    """``iterable`` with a bar "what: n/N [elapsed]" (nothing when not shown)."""
    return tqdm(iterable, desc=what, total=total, unit=unit, disable=not shown(progress),
                file=sys.stderr, leave=False, mininterval=0.3, **_screen())


@contextmanager
def waiting(what, progress=None):
    """A running clock "what … 12 s" while a step without parts (a spreadsheet engine's
    run) goes on."""
    if not shown(progress):
        yield
        return
    bar = tqdm(desc=what, total=None, file=sys.stderr, leave=False,
               bar_format="{desc} … {elapsed}", **_screen())
    done = threading.Event()

    def tick():
        while not done.wait(0.5):
            bar.refresh()
    clock = threading.Thread(target=tick, daemon=True)
    clock.start()
    try:
        yield
    finally:
        done.set()
        clock.join()
        bar.close()
