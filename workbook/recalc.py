"""Recalculate workbooks in LibreOffice headless, with recalculation on load forced.

LibreOffice keeps the cached values of an .xlsx by default; a private profile
whose OOXMLRecalcMode is 0 ("always") makes it recompute every formula, and
converting the file back to .xlsx stores the recomputed values.
"""
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from workbook.errors import RecalculationError

PROFILE_SETTINGS = """<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry"
 xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="ODFRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Common/Misc"><prop oor:name="FirstRun" oor:op="fuse"><value>false</value></prop></item>
</oor:items>
"""
CANDIDATES = ["soffice", "libreoffice", "/usr/lib/libreoffice/program/soffice",
              "/opt/libreoffice/program/soffice"]


def find_soffice():
    """Path of the LibreOffice executable, or None."""
    for candidate in CANDIDATES:
        found = shutil.which(candidate) or (candidate if os.path.isfile(candidate) else None)
        if found:
            return found
    return None


def make_profile(directory):
    """A LibreOffice user profile in ``directory`` that recalculates on load."""
    user = Path(directory) / "user"
    user.mkdir(parents=True, exist_ok=True)
    (user / "registrymodifications.xcu").write_text(PROFILE_SETTINGS, encoding="utf-8")
    return Path(directory).resolve().as_uri()


def convert(paths, outdir, target="xlsx", timeout=600):
    """Open each of ``paths`` in one LibreOffice process with recalculation forced and
    save it as ``target`` in ``outdir``; return the output paths in order."""
    soffice = find_soffice()
    if soffice is None:
        raise RecalculationError("LibreOffice (soffice) is not installed; install Debian's "
                                 "libreoffice-calc-nogui")
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="crankbook-lo-") as profile:
        command = [soffice, f"-env:UserInstallation={make_profile(profile)}", "--headless",
                   "--norestore", "--nolockcheck", "--convert-to", target,
                   "--outdir", str(outdir)] + [str(p) for p in paths]
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                                  env={**os.environ, "HOME": profile})
        except subprocess.TimeoutExpired:
            raise RecalculationError(f"LibreOffice did not finish within {timeout} s") from None
    outputs = [outdir / (Path(p).stem + "." + target.split(":")[0]) for p in paths]
    missing = [str(p) for p in outputs if not p.is_file()]
    if missing:
        raise RecalculationError("LibreOffice wrote no " + ", ".join(missing)
                                 + f": {done.stderr.strip() or done.stdout.strip()}")
    return outputs
