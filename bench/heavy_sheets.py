"""Benchmark: build and verify time of the heaviest default workbook against a base commit.

The multi-cylinder presets carry the widest sheet (Operating parts: a pressure, its
forces and every throw's and journal's loads per operating point).  This builds and
verifies one (default inline-4) with the working tree's crankbook and with the
``--base`` commit's (default HEAD~1), side by side: runs alternate, the best of each
is kept, and the ratios say what a change cost.  Each side runs in its own Python
with the package assembled from that tree, so the editable install does not leak in.
Budget: ratio ≤ 3 for a change that adds a quantity per operating point (a pressure
per speed multiplies the sheet by the number of points), ≤ 1.2 otherwise.

    .venv/bin/python bench/heavy_sheets.py [--base REV] [--preset inline-4] [--repeat N]
"""
import argparse
import json
import os
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RUN = r"""
import json, sys, time, zipfile
import crankbook
preset, path, verify = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
started = time.perf_counter()
crankbook.compute(preset).to_excel(path)
built = time.perf_counter() - started
checked = None
if verify:
    started = time.perf_counter()
    ok = bool(crankbook.verify(path, progress=False)["ok"].all())
    checked = time.perf_counter() - started
size = sum(i.file_size for i in zipfile.ZipFile(path).infolist())
print(json.dumps({"build": built, "verify": checked, "unpacked": size,
                  "ok": ok if verify else None}))
"""


def assemble(tree, into):
    """The package ``crankbook`` as the wheel lays it out, from a source tree, by links:
    workbook/ is crankbook, calc/ crankbook.calc, templates/ crankbook.templates."""
    package = into / "crankbook"
    package.mkdir(parents=True)
    for entry in (tree / "workbook").iterdir():
        (package / entry.name).symlink_to(entry)
    (package / "calc").symlink_to(tree / "calc")
    (package / "templates").symlink_to(tree / "templates")
    return into


def run(side, preset, out, verify):
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(side), sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])}
    done = subprocess.run([sys.executable, "-S", "-c", RUN, preset, str(out),
                           "1" if verify else "0"],
                          capture_output=True, text=True, env=environment, check=False)
    if done.returncode:
        raise SystemExit(f"bench: {side}: {done.stderr.strip().splitlines()[-1]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="HEAD~1")
    parser.add_argument("--preset", default="inline-4")
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--no-verify", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        base_tree = tmp / "base-tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q",
                        str(base_tree), args.base], check=True)
        try:
            sides = {"base": assemble(base_tree, tmp / "base"),
                     "current": assemble(ROOT, tmp / "current")}
            best = {}
            for attempt in range(args.repeat):
                for name, side in sides.items():
                    got = run(side, args.preset, tmp / f"{name}.xlsx", not args.no_verify)
                    keep = best.setdefault(name, got)
                    for key in ("build", "verify"):
                        if got[key] is not None and got[key] < keep[key]:
                            keep[key] = got[key]
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                            str(base_tree)], check=False)
    print(f"{args.preset}: {args.base} against the working tree (best of {args.repeat})")
    print(f"{'':<28}{'base [s]':>10}{'current [s]':>13}{'ratio':>8}")
    for key in ("build", "verify"):
        if best["base"][key] is None:
            continue
        b, c = best["base"][key], best["current"][key]
        print(f"{key:<28}{b:>10.1f}{c:>13.1f}{c / b:>8.2f}")
    b, c = best["base"]["unpacked"] / 1e6, best["current"]["unpacked"] / 1e6
    print(f"{'unpacked size [MB]':<28}{b:>10.1f}{c:>13.1f}{c / b:>8.2f}")
    if best["current"]["ok"] is False:
        print("current: verify found names that differ from numpy")


if __name__ == "__main__":
    main()
