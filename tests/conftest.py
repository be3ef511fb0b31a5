"""Shared fixtures.  LibreOffice tests fail, never skip, when soffice is missing: the
cross-checks are the point of the suite, and ./dev test installs LibreOffice."""
import subprocess
import sys
from pathlib import Path

import pytest

from crankbook.recalc import find_soffice, find_ssconvert

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def soffice():
    path = find_soffice()
    if path is None:
        pytest.fail("LibreOffice (soffice) is not installed: run ./dev test, or "
                    "apt-get install libreoffice-calc-nogui")
    return path


def run_cli(*args, cwd=None):
    """Run ``python -m workbook`` as a user would; returns the CompletedProcess."""
    return subprocess.run([sys.executable, "-m", "crankbook", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd or ROOT, timeout=600)
