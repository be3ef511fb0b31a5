"""Benchmark: assign a 100-student class and grade its 100 returned workbooks.

Targets (issue 10): assign under 20 s and grade under 10 s on this two-core machine.  The returned
workbooks are the students' files with every answer filled in from the keys
(filling them is set-up, not timed).

    .venv/bin/python bench/class_pack.py [--students N]
"""
import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run(*args):
    """(wall seconds, CPU seconds of the command and its workers)."""
    import resource
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "crankbook", *map(str, args)], check=True, cwd=ROOT,
                   stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return time.perf_counter() - started, cpu


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--students", type=int, default=100)
    args = parser.parse_args()
    import openpyxl

    from crankbook.assignment import template
    from crankbook.reading.workbook_reader import cells as read_cells, defined_ranges, open_book

    def named_values(path):
        book = open_book(path)
        return {name: read_cells(book, found) for name, found in defined_ranges(book).items()}

    items = [i.key for i in template.load("course-design").items]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        ids = [f"st{n:03d}" for n in range(args.students)]
        (tmp / "roster.csv").write_text("student_id,name\n" + "".join(f"{i},N {i}\n" for i in ids))
        assign = run("assign", "--roster", tmp / "roster.csv", "--seed", "3", "-o", tmp / "class")
        (tmp / "returned").mkdir()
        for sid in ids:                                   # the returned, filled-in workbooks
            key = named_values((tmp / "class" / "keys" / f"{sid}.xlsx"))
            book = openpyxl.load_workbook(tmp / "class" / "students" / f"{sid}.xlsx")
            for item in items:
                sheet, ref = next(iter(book.defined_names[f"a_{item}"].destinations))
                block = book[sheet][ref.replace("$", "")]
                cells = [c for row in block for c in row] if isinstance(block, tuple) else [block]
                values = key[f"q_{item}"]
                for cell, value in zip(cells, values):
                    cell.value = value
            book.save(tmp / "returned" / f"{sid}.xlsx")
        grade = run("grade", tmp / "class", tmp / "returned", "-o", tmp / "results")
        shutil.rmtree(tmp / "class")
    n = args.students
    print(f"{'':<28}{'time [s]':>10}{'CPU per student [s]':>22}")
    for what, (seconds, cpu), target in (("assign", assign, 20.0), ("grade", grade, 10.0)):
        scaled = target * n / 100
        verdict = "met" if seconds < scaled else "MISSED"
        print(f"{f'{what} {n} students':<28}{seconds:>10.1f}{cpu / n:>22.3f}   "
              f"target under {scaled:.0f} s ({verdict})")


if __name__ == "__main__":
    main()
