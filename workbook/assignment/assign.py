"""`crankbook assign`: a workbook per student, the answer keys and a manifest.

The class directory is built in a hidden sibling and renamed into place when
complete (a killed run leaves nothing the next run does not remove); the work is
shared by worker processes that die with their parent.
"""
import json
import gc
import os
from concurrent.futures import ProcessPoolExecutor
from functools import lru_cache
from pathlib import Path

from crankbook import __version__

from crankbook.spec import params

from crankbook.support import resources
from crankbook.assignment import template as templates
from crankbook.assignment.groups import fixed_values
from crankbook.assignment.key import answer_rows, given_trace, key_results
from crankbook.assignment.roster import read_roster
from crankbook.assignment.student_book import write_student_workbook
from crankbook.assignment.variants import draw_class, fingerprint
from crankbook.support.csv_safety import csv_text, kept_text
from crankbook.assignment.results import words
from crankbook.support.progress import steps, waiting
from crankbook.support.workspace import check_directory, staged_directory
from crankbook.writer.build import write_workbook

MANIFEST = "manifest.csv"
SETTINGS = "assignment.json"
RUBRIC = "assignment.toml"


def _die_with_parent():
    """Worker initializer: be killed when the parent process dies (Linux); collect
    cycles every few students instead of during the writing (a fifth of its time)."""
    gc.disable()
    try:
        import ctypes
        import signal
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)   # PR_SET_PDEATHSIG
        if os.getppid() == 1:
            os._exit(1)
    except (OSError, AttributeError):
        pass


@lru_cache(maxsize=None)
def _setup(preset, assignment_key, assignment_file=None):
    spec, _, meta = params.load_preset(preset)
    return spec, meta, templates.load(assignment_key, Path(assignment_file)
                                      if assignment_file else None)


_WRITTEN = [0]


def write_student(job):
    """Write one student's key and workbook (runs in a worker process)."""
    _WRITTEN[0] += 1
    if _WRITTEN[0] % 10 == 0 and not gc.isenabled():
        gc.collect()
    preset, (assignment_key, assignment_file), row, drawn, lang, staging = job
    spec, meta, assignment = _setup(preset, assignment_key, assignment_file)
    staging = Path(staging)
    sid = row["student_id"]
    values = params.validate(spec, dict(drawn))
    key = key_results(assignment, spec, meta, values)
    write_workbook(key, lang, staging / "keys" / f"{sid}.xlsx")
    trace = given_trace(assignment, spec, values)
    given = {"crank_angle": trace[0], "pressure": trace[1]} if trace is not None else {}
    write_student_workbook(staging / "students" / f"{sid}.xlsx", assignment, spec, row, values,
                           given, lang, answer_rows(assignment, lang, key.results, spec))
    return sid


def _manifest_value(value):
    """A parameter as the manifest keeps it: a number, or [a,b,…] for a per-item one
    (never text a spreadsheet would take for a formula)."""
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(repr(float(v)) for v in value) + "]"
    return float(value)


def assign(preset, roster_path, seed, lang, outdir, progress=None, groups=None,
           assignment_file=None):
    """Write the class directory; ``groups``: None, "preset" (the preset's group table)
    or a teacher's group table file — each roster group shares that row's values;
    ``assignment_file``: a teacher's own assignment template (its preset is used)."""
    outdir = check_directory(outdir)          # before any work: a bad -o is one line now
    if assignment_file is not None:
        assignment = templates.load(Path(assignment_file).stem, Path(assignment_file))
        preset = assignment.preset
    spec, base, meta = params.load_preset(preset)       # an unknown preset is named first
    if assignment_file is None:
        assignment = templates.for_preset(preset)
    rows, fields = read_roster(roster_path)
    ids = [r["student_id"] for r in rows]
    fixed = fixed_values(spec, meta, groups, rows) if groups else None
    w = words(lang)
    with waiting(w["progress_drawing"].format(count=len(ids)), progress):
        variants = draw_class(assignment, spec, base, ids, seed, fixed)
    keys = [p.key for p in spec.parameters]
    with staged_directory(outdir) as staging:
        (staging / "keys").mkdir()
        (staging / "students").mkdir()
        source = (assignment.key, str(Path(assignment_file).resolve()) if assignment_file
                  else None)
        jobs = [(preset, source, row, variants[row["student_id"]], lang, str(staging))
                for row in rows]
        workers = max(1, min(os.cpu_count() or 1, len(jobs)))
        with ProcessPoolExecutor(max_workers=workers, initializer=_die_with_parent) as pool:
            for _ in steps(pool.map(write_student, jobs, chunksize=2), w["progress_writing"],
                           total=len(jobs), progress=progress, unit="student"):
                pass
        extra = [f for f in fields if f not in ("student_id", "name")]
        table = [["student_id", "name", *extra, *[f"p_{k}" for k in keys], "fingerprint"]]
        for row in rows:
            values = variants[row["student_id"]]
            table.append([kept_text(row["student_id"]), row["name"],
                          *[kept_text(row.get(f, "")) for f in extra],
                          *[_manifest_value(values[k]) for k in keys], fingerprint(values, keys)])
        (staging / MANIFEST).write_text(csv_text(table), encoding="utf-8-sig", newline="")
        # the class keeps the template it was assigned with: grade reads this copy
        (staging / RUBRIC).write_text(
            Path(assignment_file).read_text(encoding="utf-8") if assignment_file else
            resources.read_text(templates.ASSIGNMENTS, f"{assignment.key}.toml"),
            encoding="utf-8")
        (staging / SETTINGS).write_text(json.dumps(
            {"assignment": assignment.key, "preset": preset, "seed": seed, "lang": lang,
             "groups": str(groups) if groups else None,
             "crankbook": __version__}, indent=1) + "\n", encoding="utf-8")
    return len(rows)
