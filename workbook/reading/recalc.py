"""Recalculate workbooks in a real spreadsheet engine: LibreOffice or Gnumeric.

LibreOffice keeps the cached values of an .xlsx by default; a private profile
whose OOXMLRecalcMode is 0 ("always") makes it recompute every formula.  Gnumeric's
``ssconvert --recalc`` recomputes before saving.  ``convert`` saves what an engine
computed as a file (.xlsx, .pdf, …); ``computed_values`` has it write only the values,
every sheet as CSV, in half the time — what verify, read and audit need.  Each run
gets its own profile and home directory, removed afterwards whatever happened.
"""
import os
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

from crankbook.errors import RecalculationError
from crankbook.support.workspace import record_engine, sweep_temporary, temporary_directory

PROFILE_SETTINGS = """<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry"
 xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="ODFRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Common/Misc"><prop oor:name="FirstRun" oor:op="fuse"><value>false</value></prop></item>
</oor:items>
"""
SOFFICE = ["soffice", "libreoffice", "/usr/lib/libreoffice/program/soffice",
           "/opt/libreoffice/program/soffice"]
SSCONVERT = ["ssconvert", "/usr/bin/ssconvert"]
ENGINES = ("libreoffice", "gnumeric")


def _find(candidates):
    for candidate in candidates:
        found = shutil.which(candidate) or (candidate if os.path.isfile(candidate) else None)
        if found:
            return found
    return None


def find_soffice():
    """Path of the LibreOffice executable, or None."""
    return _find(SOFFICE)


def find_ssconvert():
    """Path of Gnumeric's ssconvert, or None."""
    return _find(SSCONVERT)


def make_profile(directory):
    """A LibreOffice user profile in ``directory`` that recalculates on load."""
    user = Path(directory) / "user"
    user.mkdir(parents=True, exist_ok=True)
    (user / "registrymodifications.xcu").write_text(PROFILE_SETTINGS, encoding="utf-8")
    return Path(directory).resolve().as_uri()


def _death_signal():
    """A function that, called in the engine's process before it starts, has Linux
    SIGKILL it when crankbook dies, however crankbook dies (prctl PR_SET_PDEATHSIG;
    its own children are reaped by the next run through the scratch folder's
    record) — or None off Linux.  The C function is found here, in the parent: the
    child between fork and exec only calls it (no import, no dlopen, no lock)."""
    if sys.platform != "linux":
        return None
    try:
        import ctypes
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    return lambda: prctl(1, signal.SIGKILL)                              # PR_SET_PDEATHSIG


class Cancel:
    """A handle on the engine runs of one caller, to give up on them from another
    thread (Ctrl-C, an unreadable workbook).  The engine runs in a session of its own,
    out of the terminal's Ctrl-C, and the thread waiting on it would hold the caller
    until it finished; ``cancel()`` kills what runs and refuses what would start."""

    def __init__(self):
        self._lock = threading.Lock()
        self._processes = set()
        self.cancelled = False

    def started(self, process):
        """Whether ``process`` may go on (False: the caller has given up already)."""
        with self._lock:
            if not self.cancelled:
                self._processes.add(process)
            return not self.cancelled

    def finished(self, process):
        with self._lock:
            self._processes.discard(process)

    def cancel(self):
        with self._lock:
            self.cancelled = True
            for process in self._processes:
                if process.poll() is None:    # not yet reaped: its group is still ours
                    os.killpg(process.pid, 9)


def _run(command, timeout, home, cancel=None):
    """Run ``command`` in its own process group; kill the whole group on timeout or when
    ``cancel`` (a Cancel) is cancelled.  Its HOME and TMPDIR are the scratch folder
    ``home``, so what the engine leaves (its profile, LibreOffice's lu*.tmp) goes with
    the folder."""
    if cancel is not None and cancel.cancelled:
        raise RecalculationError(f"{Path(command[0]).name} was not started: cancelled")
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "HOME": home, "TMPDIR": home},
                               start_new_session=True,
                               preexec_fn=_death_signal())
    record_engine(home, process.pid)      # a killed run's engine: the next run ends it
    try:
        if cancel is not None and not cancel.started(process):
            os.killpg(process.pid, 9)
        out, err = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, 9)
        process.communicate()
        raise RecalculationError(f"{Path(command[0]).name} did not finish within "
                                 f"{timeout} s") from None
    except BaseException:
        os.killpg(process.pid, 9)
        process.communicate()
        raise
    finally:
        if cancel is not None:
            cancel.finished(process)
    return process.returncode, out, err


def require_engine(engine):
    """The engine's program, or a RecalculationError that says how to install it."""
    if engine == "gnumeric":
        ssconvert = find_ssconvert()
        if ssconvert is None:
            raise RecalculationError("Gnumeric (ssconvert) is not installed; install Debian's "
                                     "gnumeric")
        return ssconvert
    if engine != "libreoffice":
        raise RecalculationError(f"unknown engine {engine!r}; engines are {', '.join(ENGINES)}")
    soffice = find_soffice()
    if soffice is None:
        raise RecalculationError("LibreOffice (soffice) is not installed; install Debian's "
                                 "libreoffice-calc-nogui")
    return soffice


def convert(paths, outdir, target="xlsx", timeout=600, engine="libreoffice", cancel=None):
    """Recalculate each of ``paths`` in ``engine`` and save it as ``target`` in
    ``outdir``; return the output paths in order.  ``cancel``: a Cancel another thread
    may use to stop the engine."""
    program = require_engine(engine)
    sweep_temporary()                     # what killed runs left: engines, copies
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    outputs = [outdir / (Path(p).stem + "." + target.split(":")[0]) for p in paths]
    if engine == "gnumeric":
        with temporary_directory("gnumeric") as home:
            for source, output in zip(paths, outputs):
                code, out, err = _run([program, "--recalc", str(source), str(output)],
                                      timeout, home, cancel)
                if not output.is_file():
                    raise RecalculationError(f"Gnumeric wrote no {output}: "
                                             f"{(err or out).strip()[:300]}")
        return outputs
    with temporary_directory("lo") as profile:
        command = [program, f"-env:UserInstallation={make_profile(profile)}", "--headless",
                   "--norestore", "--nolockcheck", "--convert-to", target,
                   "--outdir", str(outdir)] + [str(p) for p in paths]
        code, out, err = _run(command, timeout, profile, cancel)
    missing = [str(p) for p in outputs if not p.is_file()]
    if missing:
        raise RecalculationError("LibreOffice wrote no " + ", ".join(missing)
                                 + f": {(err or out).strip()[:300]}")
    return outputs


# LibreOffice's CSV filter: comma, double quote, UTF-8 (76), from line 1, every text
# cell quoted (so text is told from numbers), values not as shown (full precision, no
# format), no formulas, every sheet (-1) to its own <name>-<sheet>.csv
LIBREOFFICE_CSV = 'csv:Text - txt - csv (StarCalc):44,34,76,1,,0,true,true,false,false,false,-1'
GNUMERIC_CSV = ["-S", "--export-type=Gnumeric_stf:stf_assistant",
                "-O", "format=raw separator=, quoting-mode=auto"]


def computed_values(paths, outdir, timeout=600, engine="libreoffice", cancel=None):
    """Recalculate each of ``paths`` in ``engine`` and return what it computed, one
    engine_values.ComputedValues per path: the engine writes every sheet's values as
    CSV, which costs it half of saving the workbook (see engine_values).  The
    workbooks are copied in under numbered names first, so no two files' sheets can
    meet under one CSV name.  An older LibreOffice, which writes one sheet only, saves
    the workbook back instead (an XlsxBook, with the same ``values``)."""
    from crankbook.reading.engine_values import ComputedValues
    from crankbook.reading.workbook_reader import open_book
    program = require_engine(engine)
    for path in paths:                    # sheet names become file names: Excel's only
        open_book(path).close()           # (WorkbookReadError naming the file otherwise)
    sweep_temporary()
    outdir = Path(outdir)
    staged = outdir / "in"
    staged.mkdir(parents=True, exist_ok=True)
    inputs = []
    for number, path in enumerate(paths):
        inputs.append(staged / f"{number:05d}.xlsx")
        shutil.copyfile(path, inputs[-1])
    if engine == "gnumeric":
        with temporary_directory("gnumeric") as home:
            for source in inputs:
                _run([program, "--recalc", *GNUMERIC_CSV, str(source),
                      str(outdir / f"{source.stem}-%s.csv")], timeout, home, cancel)
    else:
        with temporary_directory("lo") as profile:
            _run([program, f"-env:UserInstallation={make_profile(profile)}", "--headless",
                  "--norestore", "--nolockcheck", "--convert-to", LIBREOFFICE_CSV,
                  "--outdir", str(outdir)] + [str(p) for p in inputs], timeout, profile, cancel)
    out = []
    for path, source in zip(paths, inputs):
        found = {file.name[len(source.stem) + 1:-len(".csv")]: file
                 for file in outdir.glob(f"{source.stem}-*.csv")}
        if found:
            out.append(ComputedValues(path, found))
        elif engine == "libreoffice" and (outdir / f"{source.stem}.csv").is_file():
            out.append(_saved_back(path, source, outdir, timeout, cancel))
        else:
            raise RecalculationError(f"{engine} computed nothing for {path}")
    return out


def _saved_back(path, source, outdir, timeout, cancel):
    """The values of a workbook LibreOffice saved back as .xlsx, read by the bounded
    reader: a LibreOffice before 7.2 writes only the first sheet as CSV (one
    ``<file>.csv``, no sheet in its name), so its values are read as they were before
    crankbook asked for CSV."""
    from crankbook.reading.workbook_reader import open_book
    book = open_book(convert([source], outdir / "saved", timeout=timeout, cancel=cancel)[0])
    book.path = Path(path)                # messages name the user's file, not the copy
    return book
