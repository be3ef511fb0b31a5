"""Benchmark: verify 20 workbooks in one spreadsheet-engine start, against the engine's
own batch run writing the values it computes for the same files, every sheet as CSV
(the floor: verify cannot be faster than the engine recalculating them and writing
what it computed).  Target: ratio ≤ 1.5.

    .venv/bin/python bench/verify_many.py [--files N] [--engine libreoffice|gnumeric]
"""
import argparse
import tempfile
import time
from pathlib import Path

import crankbook
from crankbook.reading import recalc


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=20)
    parser.add_argument("--engine", choices=recalc.ENGINES, default="libreoffice")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        paths = []
        for number in range(args.files):          # 20 different engines, 5° grids
            path = tmp / f"w{number:02d}.xlsx"
            crankbook.compute("thesis", step=5.0, speed=2000.0 + 100 * number).to_excel(path)
            paths.append(path)
        started = time.perf_counter()
        recalc.computed_values(paths, tmp / "floor", engine=args.engine)
        floor = time.perf_counter() - started
        started = time.perf_counter()
        frames = crankbook.verify(paths, engine=args.engine, progress=False)
        verify = time.perf_counter() - started
    agree = sum(bool(f.ok.all()) for f in frames)
    print(f"{'':<40}{'time [s]':>10}{'ratio':>8}")
    print(f"{f'{args.engine} batch values ({args.files} files)':<40}{floor:>10.1f}{1:>8.2f}")
    print(f"{f'crankbook verify ({args.files} files)':<40}{verify:>10.1f}{verify / floor:>8.2f}"
          f"   target ≤ 1.50; {agree}/{len(frames)} agree")


if __name__ == "__main__":
    main()
