"""Shared fixtures.  LibreOffice tests fail (not skip) under CI when soffice is missing."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from workbook.recalc import find_soffice

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def soffice():
    path = find_soffice()
    if path is None:
        message = "LibreOffice (soffice) is not installed: apt-get install libreoffice-calc-nogui"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    return path


def run_cli(*args, cwd=None):
    """Run ``python -m workbook`` as a user would; returns the CompletedProcess."""
    return subprocess.run([sys.executable, "-m", "workbook", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd or ROOT, timeout=600)
