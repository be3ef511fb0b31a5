"""Benchmark: `crankbook audit` of a workbook whose input was typed over without a
recalculation (every result cell stale: one finding naming the input), against the
audit of the same workbook untouched (the floor: the same reading and the same numpy).
Target: ratio ≤ 1.5.  Grouping the stale cells once took 29 times the floor: a search
over the 10⁵ differing cells for each of them.

    .venv/bin/python bench/audit_stale.py [--preset thesis] [--step 10]
"""
import argparse
import re
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import openpyxl

import crankbook


def typed_over(source, target, name, factor):
    """``source`` with the input ``name``'s cell holding ``factor`` times its value, as
    a user's edit with calculation set to manual leaves it: the results untouched."""
    book = openpyxl.load_workbook(source, read_only=True)
    sheet, ref = next(iter(book.defined_names[name].destinations))
    cell = ref.replace("$", "")
    part = f"xl/worksheets/sheet{book.sheetnames.index(sheet) + 1}.xml"
    value = book[sheet][cell].value * factor
    book.close()
    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == part:
                data = re.sub(rf'(<c r="{cell}"[^>]*>)<v>[^<]*</v>'.encode(),
                              lambda m: m.group(1) + f"<v>{value!r}</v>".encode(), data, count=1)
            zout.writestr(item, data)


def audited(path):
    """Seconds the command takes, and its exit code (1: findings)."""
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "crankbook", "audit", str(path)],
                          capture_output=True, text=True, check=False)
    return time.perf_counter() - started, done.returncode


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="thesis")
    parser.add_argument("--step", type=float, default=10.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        fresh, stale = Path(tmp) / "fresh.xlsx", Path(tmp) / "stale.xlsx"
        crankbook.compute(args.preset, step=args.step).to_excel(fresh)
        typed_over(fresh, stale, "p_bore", 1.09)
        floor, fresh_code = audited(fresh)
        took, stale_code = audited(stale)
    print(f"{'':<44}{'time [s]':>10}{'ratio':>8}")
    print(f"{'audit, untouched (exit ' + str(fresh_code) + ')':<44}{floor:>10.1f}{1:>8.2f}")
    print(f"{'audit, p_bore typed over (exit ' + str(stale_code) + ')':<44}{took:>10.1f}"
          f"{took / floor:>8.2f}   target ≤ 1.50")


if __name__ == "__main__":
    main()
