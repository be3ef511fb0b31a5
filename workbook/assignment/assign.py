"""`crankbook assign`: a workbook per student, the answer keys and a manifest."""
import csv
import json
import os
import shutil
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from crankbook import __version__, evaluate, params
from crankbook.assignment import template as templates
from crankbook.assignment.student_book import write_student_workbook
from crankbook.assignment.variants import draw_class, fingerprint, read_roster
from crankbook.errors import BuildOptionError
from crankbook import resources
from crankbook.api import results_for
from crankbook.writer.build import write_workbook

MANIFEST = "manifest.csv"
SETTINGS = "assignment.json"
RUBRIC = "assignment.toml"


def given_data(assignment, spec, values):
    """The numbers a student is given (e.g. the cylinder pressure every degree)."""
    if not assignment.given:
        return {}
    grid = evaluate.crank_angle_grid(spec, assignment.given_step) if assignment.given_step \
        else expected_grid(assignment, spec)
    out = evaluate.evaluate(spec, values, {}, grid)
    return {key: [float(v) for v in out[key]] for key in assignment.given}


def expected_grid(assignment, spec, step=None):
    if assignment.grid_angles is not None:
        import numpy as np
        return np.asarray(assignment.grid_angles, dtype=float)
    return evaluate.crank_angle_grid(spec, step)


def _write_student(job):
    """Write one student's key and workbook (runs in a worker process)."""
    preset, assignment_key, row, drawn, lang, staging = job
    spec, _, preset_meta = params.load_preset(preset)
    assignment = templates.load(assignment_key)
    staging = Path(staging)
    sid = row["student_id"]
    values = params.validate(spec, dict(drawn))
    key = results_for(spec, preset_meta, values)
    write_workbook(key, lang, staging / "keys" / f"{sid}.xlsx")
    expected = evaluate.evaluate(spec, values, {}, expected_grid(assignment, spec)) \
        if assignment.grid_angles is not None else key.results
    sizes = {g.key: len(expected[g.key]) for g in spec.grids}
    write_student_workbook(staging / "students" / f"{sid}.xlsx", assignment, spec, row, values,
                           given_data(assignment, spec, values), lang, sizes)
    return sid


def assign(preset, roster_path, seed, lang, outdir, progress=True):
    spec, base, preset_meta = params.load_preset(preset)
    assignment = templates.for_preset(preset)
    rows, fields = read_roster(roster_path)
    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise BuildOptionError(f"-o {outdir}: is a file; give a new directory")
    if outdir.exists() and any(outdir.iterdir()):
        raise BuildOptionError(f"-o {outdir}: exists and is not empty; give a new directory")
    ids = [r["student_id"] for r in rows]
    variants = draw_class(assignment, spec, base, ids, seed)
    keys = [p.key for p in spec.parameters]
    outdir.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{outdir.name}.", dir=outdir.parent))
    try:
        jobs = [(preset, assignment.key, row, variants[row["student_id"]], lang, str(staging))
                for row in rows]
        workers = max(1, min(os.cpu_count() or 1, len(jobs)))
        with ProcessPoolExecutor(max_workers=workers) as pool:
            for number, _ in enumerate(pool.map(_write_student, jobs), start=1):
                if progress:
                    print(f"\rassign: {number}/{len(rows)} students", end="", file=sys.stderr,
                          flush=True)
        if progress:
            print(file=sys.stderr)
        extra = [f for f in fields if f not in ("student_id", "name")]
        with open(staging / MANIFEST, "w", newline="", encoding="utf-8") as handle:
            writer = csv.writer(handle, lineterminator="\n")
            writer.writerow(["student_id", "name", *extra, *[f"p_{k}" for k in keys],
                             "fingerprint"])
            for row in rows:
                values = variants[row["student_id"]]
                writer.writerow([row["student_id"], row["name"], *[row.get(f, "") for f in extra],
                                 *[repr(float(values[k])) for k in keys],
                                 fingerprint(values, keys)])
        (staging / RUBRIC).write_text(resources.read_text(templates.ASSIGNMENTS,
                                                          f"{assignment.key}.toml"),
                                      encoding="utf-8")
        (staging / SETTINGS).write_text(json.dumps(
            {"assignment": assignment.key, "preset": preset, "seed": seed, "lang": lang,
             "crankbook": __version__}, indent=1) + "\n", encoding="utf-8")
        if outdir.exists():
            outdir.rmdir()
        os.replace(staging, outdir)
    finally:
        if staging.exists():
            shutil.rmtree(staging)
    return len(rows)
