"""Command line: ``crankbook`` or ``python -m crankbook``, a thin layer over the API.

Every user error is a CrankbookError, caught here once and printed as one line
(exit code 2); nothing is written when a build fails.
"""
import argparse
import contextlib
import os
import sys
import time
import warnings

from crankbook import __version__
from crankbook.errors import BuildOptionError, CrankbookError, CrankbookWarning

LANGS = ("zh", "en")


class _Parser(argparse.ArgumentParser):
    """argparse with its errors in one line, like every other crankbook error."""

    def error(self, message):
        print(f"crankbook: error: {_one_line(message)} (see '{self.prog} --help')",
              file=sys.stderr)
        raise SystemExit(2)


def _one_line(message):
    """A message as one line, every echoed word of input cut to 80 characters."""
    import re
    message = " ".join(str(message).split())
    return re.sub(r"\S{81,}", lambda m: m.group(0)[:60] + "…" + m.group(0)[-12:], message)[:600]


def _plain_number(text):
    """A number option as --set reads one: ASCII decimals only (not 1_000, １２, nan or
    inf, which Python's float() would take)."""
    from crankbook.spec.params import NUMBER
    stripped = text.strip()
    if not NUMBER.match(stripped):
        raise argparse.ArgumentTypeError(f"{text[:40]!r} is not a plain decimal number")
    return float(stripped)


def _plain_positive(text):
    value = _plain_number(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text[:40]!r} must be a number > 0")
    return value


def _plain_whole(text):
    stripped = text.strip()
    if not stripped.isascii() or not stripped.isdigit():
        raise argparse.ArgumentTypeError(f"{text[:40]!r} is not a whole number of ASCII "
                                         f"digits")
    return int(stripped)


def _build_parser():
    parser = _Parser(
        prog="crankbook",
        description="Formula-backed Excel workbooks of crank–connecting-rod mechanisms.")
    parser.add_argument("--version", action="version", version=f"crankbook {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    build = commands.add_parser(
        "build", help="write a workbook for a preset",
        description="Write a formula-backed workbook: a Parameters sheet of named inputs, "
                    "one sheet per quantity with a chart, and a Summary.")
    build.add_argument("--preset", default="thesis",
                       help="parameter preset (default: thesis; see 'crankbook presets')")
    build.add_argument("--group", type=int, metavar="N",
                       help="class group N of the preset's group table (course-design: 1–12), "
                            "applied before --set")
    build.add_argument("--set", dest="assignments", action="append", default=[],
                       metavar="KEY=VALUE", help="override a parameter, in its sheet unit "
                       "(repeatable), e.g. --set speed=3000 --set offset=5")
    build.add_argument("--pressure", metavar="FILE",
                       help="measured cylinder pressure: .csv or .xlsx, two columns crank angle "
                            "[deg] and absolute pressure [MPa]; sets pressure_source = 1 unless "
                            "--set says otherwise")
    build.add_argument("--lang", choices=LANGS, default="zh",
                       help="language of sheet names, titles and charts (default: zh); "
                            "labels are bilingual either way")
    build.add_argument("--step", type=_plain_number, default=None, metavar="DEG",
                       help="crank-angle grid step in degrees, dividing the cycle (default: 1)")
    build.add_argument("--cam-step", type=_plain_number, default=None, metavar="DEG",
                       help="cam-angle grid step in degrees of the course design's cams "
                            "(default: 1)")
    build.add_argument("-o", "--output", metavar="PATH",
                       help="output .xlsx (default: output/<preset>.xlsx)")
    build.add_argument("-q", "--quiet", action="store_true",
                       help="no progress on the terminal (none is shown in a pipe anyway)")

    verify = commands.add_parser(
        "verify", help="recalculate workbooks in LibreOffice and compare with numpy",
        description="Open each PATH in LibreOffice headless with recalculation forced, read every "
                    "q_ name back and compare it with numpy for the workbook's own parameters. "
                    "Exit 0 only when all agree within 1e-9 of each quantity's peak plus its "
                    "rounding floor.")
    verify.add_argument("paths", metavar="PATH", nargs="+",
                        help="one or more workbooks (all recalculated in one engine start)")
    verify.add_argument("--engine", choices=("libreoffice", "gnumeric"), default="libreoffice",
                        help="spreadsheet engine that recalculates (default: libreoffice)")
    verify.add_argument("-q", "--quiet", action="store_true",
                        help="no progress on the terminal (none is shown in a pipe anyway)")

    audit = commands.add_parser(
        "audit", help="audit a source document's numbers, or a workbook crankbook wrote",
        description="DOCUMENT (thesis, course-report, compressor, offset-piston, "
                    "balancing-ring or all): every number the document states beside an "
                    "independent recomputation, with a verdict; writes an audit workbook "
                    "(live formulas), a Markdown report beside it and, with --json, the "
                    "findings as JSON. FILE.xlsx: recompute a workbook crankbook wrote from "
                    "its p_ cells and report every q_ cell that no longer agrees.")
    audit.add_argument("target", metavar="DOCUMENT|FILE.xlsx",
                       help="a document's short name (or all), or a workbook to re-audit")
    audit.add_argument("-o", "--output", metavar="PATH.xlsx",
                       help="audit workbook (default: output/audit-<document>.xlsx)")
    audit.add_argument("--json", metavar="PATH.json", help="also write the findings as JSON")
    audit.add_argument("--sources", metavar="DIR",
                       help="folder of the seed text files: check that every reported number "
                            "is printed at its line (exit 1 if one is not)")
    audit.add_argument("-q", "--quiet", action="store_true",
                       help="no progress on the terminal (none is shown in a pipe anyway)")

    assign = commands.add_parser(
        "assign", help="write a workbook per student, the answer keys and a manifest",
        description="Draw each student's parameters from the preset's assignment template "
                    "(reproducible for the same roster and --seed), and write "
                    "DIR/students/<id>.xlsx, DIR/keys/<id>.xlsx and DIR/manifest.csv.")
    assign.add_argument("--preset", default="course-design",
                        help="preset whose assignment template draws the variants "
                             "(default: course-design)")
    assign.add_argument("--roster", required=True, metavar="ROSTER",
                        help="the class list: .csv (UTF-8, GBK or UTF-16, as Excel saves it) or "
                             ".xlsx, with an id column (student_id, id or 学号) and a name "
                             "column (name or 姓名); other columns are kept")
    assign.add_argument("--seed", type=_plain_whole, default=None,
                        help="variant seed: with it and a student's id anyone who has "
                             "crankbook draws that student's key, so keep it secret (default: "
                             "a random 18-digit seed, kept in DIR/assignment.json; give it "
                             "again to draw the same tasks, e.g. for a late student)")
    assign.add_argument("--lang", choices=LANGS, default="zh",
                        help="language of the students' workbooks, feedback and reports "
                             "(default: zh)")
    assign.add_argument("-o", "--output", required=True, metavar="DIR",
                        help="a new folder for the class (refused if it exists and is not empty)")
    assign.add_argument("--assignment", metavar="FILE",
                        help="a teacher's own assignment template (a copy of "
                             "templates/assignments/course-design.toml with other ranges, "
                             "items or points); its preset is used")
    assign.add_argument("--groups", nargs="?", const="preset", metavar="FILE",
                        help="group mode: every student of a roster group (组号/group column) "
                             "shares the group's values — the preset's table (the guide's "
                             "附表1) or FILE (CSV or TOML: number/组号 and parameter keys); "
                             "the rest (the valve train) is still drawn per student")
    assign.add_argument("-q", "--quiet", action="store_true",
                        help="no progress on the terminal (none is shown in a pipe anyway)")

    export = commands.add_parser(
        "export", help="write a workbook's data for another tool (torsion: stations.csv, "
                       "harmonics.csv, response.csv; trace: a pressure trace --pressure reads; "
                       "bearing: the journal orbits)",
        description="export torsion WORKBOOK -o DIR: the torsional system (station, J, k to "
                    "the next) and each cylinder's torque harmonics a_k, b_k in the common "
                    "crank angle, total, gas and inertia parts, at the workbook's speed, "
                    "and the forced response over its speed sweep (speed, order, section, "
                    "torque amplitude, stress), read from an engine workbook's names as stored. export trace [WORKBOOK] "
                    "-o FILE.csv: its cylinder pressure (without WORKBOOK: the thesis "
                    "engine's) as a trace file for build --pressure. export bearing WORKBOOK "
                    "-o FILE.csv: the big end's and the checked main bearing's journal orbits "
                    "over the second cycle (crank angle, bearing, e_u/c, e_v/c, h_min in µm, "
                    "p_max in MPa, film broke down).")
    export.add_argument("what", choices=("torsion", "trace", "bearing"), help="what to export")
    export.add_argument("workbook", metavar="WORKBOOK", nargs="?",
                        help="an engine workbook crankbook wrote (trace: optional)")
    export.add_argument("-o", "--output", required=True, metavar="DIR|FILE.csv",
                        help="torsion: the folder for stations.csv, harmonics.csv and response.csv; "
                             "trace, bearing: the .csv file")

    check = commands.add_parser(
        "check", help="for students: would the grader read this workbook in full?",
        description="Read a returned student workbook as `crankbook grade` does and list, in "
                    "the file's language, what grading would lose: an unreadable file, text "
                    "in a number cell, rows whose crank angle names no position, blank "
                    "answers. Never a score or an expected value. Exit 0: everything would "
                    "be read; 1: something would be lost.")
    check.add_argument("file", metavar="FILE", help="your filled-in workbook (.xlsx)")

    grade = commands.add_parser(
        "grade", help="grade returned workbooks against the assignment in DIR",
        description="Grade every .xlsx under SUBMISSIONS (any names, nested folders) against "
                    "the parameters assigned in DIR; write gradebook.csv and .xlsx, an LMS import "
                    "CSV, feedback/<id>.md, class-report.xlsx and the teacher-only "
                    "integrity.xlsx to RESULTS.")
    grade.add_argument("directory", metavar="DIR", help="the class folder `assign` wrote")
    grade.add_argument("submissions", metavar="SUBMISSIONS",
                       help="the folder of returned workbooks (as the LMS or a mailbox "
                            "saves them)")
    grade.add_argument("-o", "--output", metavar="RESULTS",
                       help="results directory (default: DIR/results); replaced whole when "
                            "the new results are complete")
    grade.add_argument("--feedback", choices=("full", "hints", "score-only"), default="full",
                       help="what feedback files show: full (with the expected values), hints "
                            "(which items and cells are wrong and why, without the expected "
                            "values: for a resubmission round) or score-only")
    grade.add_argument("--previous", metavar="RESULTS",
                       help="an earlier round's results directory: a resubmission round")
    grade.add_argument("--keep", choices=("latest", "best"), default="latest",
                       help="with --previous: keep the latest score (default) or the better of "
                            "the two; a student who did not resubmit keeps the earlier score")
    grade.add_argument("--missing-as-zero", action="store_true",
                       help="write 0 for missing and unreadable students in the gradebook and "
                            "LMS import (default: blank, which an LMS reads as no submission)")
    grade.add_argument("--overrides", metavar="FILE",
                       help="the teacher's decisions, applied on every run: CSV with columns "
                            "student,item,action,points,reason,who (action accept, points or "
                            "waive-flag; item a_<key> or a_<key>!row)")
    grade.add_argument("--items", metavar="KEYS",
                       help="grade only these items (comma-separated a_ keys), e.g. this "
                            "week's part of the pack")
    grade.add_argument("--out-of", type=_plain_positive, metavar="POINTS",
                       help="scale every item so that the total is POINTS (a course weight)")
    grade.add_argument("--lms", choices=("generic", "moodle", "canvas", "xuexitong"),
                       default="generic",
                       help="also write the import file of this LMS (moodle needs "
                            "--lms-template; lms-import.csv is always written)")
    grade.add_argument("--lms-template", metavar="CSV",
                       help="the grading worksheet Moodle exported, filled in and kept whole")
    grade.add_argument("--return", dest="returns", metavar="DIR",
                       help="also write each student's own workbook back to DIR, every "
                            "answer cell coloured and commented in the class's language, a "
                            "score box on the first sheet, and DIR/<id>.html")
    grade.add_argument("-q", "--quiet", action="store_true",
                       help="no progress on the terminal (none is shown in a pipe anyway)")

    commands.add_parser("presets", help="list the presets")
    params_cmd = commands.add_parser("parameters", help="list the parameters of a preset")
    params_cmd.add_argument("--preset", default="thesis", help="preset (default: thesis)")
    params_cmd.add_argument("--group", type=int, metavar="N",
                            help="class group N of the preset's group table (course-design)")
    return parser


def _build(args):
    from crankbook.api import compute
    from crankbook.spec.params import parse_assignments

    started = time.perf_counter()
    overrides = parse_assignments(args.assignments)
    if args.cam_step is not None:
        overrides["cam_step"] = args.cam_step
    from crankbook.support.progress import waiting
    with waiting("build: computing", _progress(args)):
        results = compute(args.preset, group=args.group, pressure=args.pressure,
                          step=args.step, **overrides)
    default = args.preset if args.group is None else f"{args.preset}-group{args.group}"
    output = args.output if args.output is not None else f"output/{default}.xlsx"
    with waiting(f"build: writing {output}", _progress(args)):
        path = results.to_excel(output, lang=args.lang)
    elapsed = time.perf_counter() - started
    spec = results.spec
    unit = lambda key: "" if spec.quantity[key].unit == "-" else f" {spec.quantity[key].unit}"
    facts = ", ".join(f"{key} {_shown(results[key])}{unit(key)}" for key in spec.highlights)
    print(f"wrote {path} ({elapsed:.1f} s): {facts}")
    return 0


def _shown(value):
    return "(blank)" if value is None else f"{value:.4g}"


def _verify(args):
    from crankbook.api import verify

    started = time.perf_counter()
    frames = verify(list(args.paths), engine=args.engine, progress=_progress(args))
    worst = 0
    for path, frame in zip(args.paths, frames):
        worst = max(worst, _report_verified(path, frame))
    if len(frames) > 1:
        failed = sum(1 for f in frames if f.attrs["inputs_break_rules"] or f.attrs["valid"] != 1
                     or not f.ok.all())
        print(f"{len(frames) - failed} of {len(frames)} workbooks agree with numpy "
              f"({time.perf_counter() - started:.1f} s)")
    return worst


def _progress(args):
    """Progress on a terminal unless --quiet (tqdm stays silent in a pipe)."""
    return False if getattr(args, "quiet", False) else None


def _report_verified(path, frame):
    attrs = frame.attrs
    print(f"verify {path}: {attrs['engine']} recalculation vs numpy "
          f"({attrs['template']} workbook)")
    if attrs["inputs_break_rules"]:
        print(f"the workbook's inputs break a rule: {attrs['status']}")
        return 1
    if attrs["valid"] != 1:
        print(f"inputs are invalid in the workbook: {attrs['status']}")
        return 1
    print(f"  {'name':<46} {'cells':>6} {'worst |error|':>14} {'allowed':>10}  "
          f"{'cached':>7}  verdict")
    for row in frame.sort_values(["absent", "ratio"], ascending=[True, False]).itertuples():
        if row.absent:
            print(f"  {row.name:<46} {'':>6} {'–':>14} {'':>10}  {'':>7}  NOT IN THE WORKBOOK")
            continue
        verdict = "ok" if row.ok else "DIFFERS"
        print(f"  {row.name:<46} {row.cells:>6} {row.error:>14.3g} {row.allowed:>10.2g}  "
              f"{'ok' if row.cached_ratio <= 1 else 'differs':>7}  {verdict}")
    absent = int(frame.absent.sum())
    bad = frame[~frame.ok & ~frame.absent]
    if len(bad):
        print(f"{len(bad)} of {len(frame)} names differ from numpy")
    if absent:
        print(f"{absent} of {len(frame)} names are not in the workbook: it was built before "
              f"this crankbook computed them (or they were deleted); rebuild it with "
              f"'crankbook build' to verify them")
    if len(bad) or absent:
        return 1
    print(f"all {len(frame)} names agree with numpy")
    return 0


def _audit(args):
    from pathlib import Path

    from crankbook.audit import claims
    from crankbook.audit.book import write_audit_workbook, write_json, write_markdown

    target = args.target
    if target.lower().endswith((".xlsx", ".xlsm", ".xls")) or Path(target).is_file():
        return _audit_workbook(target)
    names = claims.document_names() if target == "all" else [target]
    documents = [claims.load(name) for name in names]
    from crankbook.writer.build import check_output
    output = check_output(args.output or f"output/audit-{target}.xlsx")
    # bad --sources is refused before anything is written; without it the seed texts
    # may come from $CRANKBOOK_SEEDS (they are needed to count the coverage)
    sources = args.sources or os.environ.get("CRANKBOOK_SEEDS") or None
    problems = _source_problems(documents, Path(sources)) if sources else None
    from crankbook.support.progress import steps
    for document in steps(documents, "audit: recomputing", progress=_progress(args),
                          unit="document"):
        document.findings()                  # computed once; the outputs read them
    write_audit_workbook(documents, output, sources)
    write_markdown(documents, output.with_suffix(".md"), sources)
    if args.json:
        write_json(documents, args.json, sources)
    for document in documents:
        findings = document.findings()
        counts = {s: sum(f["status"] == s for f in findings) for s in claims.VERDICTS}
        print(f"{document.key:<16} {len(findings):>3} claims: " +
              ", ".join(f"{n} {s}" for s, n in counts.items() if n))
    print(f"wrote {output} and {output.with_suffix('.md')}"
          + (f" and {args.json}" if args.json else ""))
    if problems is None:
        return 0
    for document_key, key, why in problems:
        print(f"{document_key}: {key}: {why}")
    print("sources: " + (f"{len(problems)} quote(s) or number(s) not found where they are said to be"
                         if problems else "every quote and reported number is where it is said to be"))
    return 1 if problems else 0


def _source_problems(documents, folder):
    """(document, claim, why) for every reported number not at its line of the seed
    files in ``folder``."""
    from crankbook.audit import claims

    problems = []
    for document in documents:
        if not (folder / document.file).is_file():
            raise BuildOptionError(f"--sources {folder}: {document.file} is not there")
        try:
            found = claims.anchor_problems(document, folder)
        except (OSError, UnicodeDecodeError) as error:
            raise BuildOptionError(f"--sources {folder}: {document.file} cannot be read as "
                                   f"UTF-8 text ({type(error).__name__})") from None
        problems += [(document.key, key, why) for key, why in found]
    return problems


def _audit_workbook(path):
    from crankbook.audit.returned import MISSING, audit_workbook

    spec, findings, recalculated, rule_message = audit_workbook(path)
    if recalculated:
        print(f"{path} was saved without calculated values: recalculated in LibreOffice first")
    if rule_message:
        print(f"{path}: its inputs break a rule: {rule_message}")
    if not findings:
        print(f"{path}: every q_ cell agrees with the recomputation from its p_ cells "
              f"({_what_it_is(path, spec)})" if not rule_message else
              f"{path}: the results that hang on those inputs are blank, as they should be; "
              f"every other q_ cell agrees ({_what_it_is(path, spec)})")
        return 1 if rule_message else 0
    print(f"{path}: {len(findings)} finding(s) against the recomputation from the p_ cells:")
    for f in findings:
        expected = "" if f.expected != f.expected else f" (expected {f.expected:.6g})"
        shown = "" if f.stored is None and f.expected != f.expected else f": {f.stored!r}"
        print(f"  {f.address:<28} {f.name:<36} {f.problem}{shown}{expected}")
    if any(f.problem == MISSING and f.name.startswith("q_") for f in findings):
        print("A workbook built by an older crankbook lacks the result names added since: "
              "audit it with the crankbook that built it, or rebuild it; otherwise a "
              "missing name was deleted")
    return 1


def _what_it_is(path, spec):
    """'course_design workbook' or 'an answer key of assignment course-design (…)'."""
    from crankbook.reading.workbook_reader import defined_ranges, open_book, role_of
    book = open_book(path)
    role, assignment = role_of(book, defined_ranges(book))
    if role == "key":
        return f"{spec.key} workbook, an answer key of assignment {assignment}"
    return f"{spec.key} workbook"


def _assign(args):
    from crankbook.assignment.assign import assign
    from crankbook.assignment.results import words
    from crankbook.assignment.variants import guessable, secret_seed

    w = words(args.lang)
    seed = secret_seed() if args.seed is None else args.seed
    if guessable(seed):
        print(w["cli_seed_guessable"].format(seed=seed), file=sys.stderr)
    started = time.perf_counter()
    count = assign(args.preset, args.roster, seed, args.lang, args.output,
                   progress=_progress(args), groups=args.groups,
                   assignment_file=args.assignment)
    print(w["cli_assigned"].format(output=args.output, count=count,
                                   seconds=time.perf_counter() - started))
    if args.seed is None:
        print(w["cli_seed_drawn"].format(seed=seed, output=args.output))
    return 0


def _stored_results(path, progress):
    """The results stored in the workbook at ``path``; or LibreOffice's recalculation
    of it, said in one line as audit says it, when the file holds none (openpyxl's
    save) or holds results its own inputs no longer give (edited with calculation set
    to manual): an export of NaN, or of another input's results, is no export."""
    import crankbook
    from crankbook.errors import StaleWorkbookWarning, UncalculatedWorkbookWarning
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = crankbook.read(path)
    reason = None
    for said in caught:
        if issubclass(said.category, UncalculatedWorkbookWarning):
            reason = "was saved without calculated values"
        elif issubclass(said.category, StaleWorkbookWarning):
            reason = (f"holds results its inputs no longer give ({said.message.name}: "
                      f"changed without recalculating?)")
        else:
            warnings.warn_explicit(said.message, said.category, said.filename, said.lineno)
    if reason is None:
        return results
    print(f"{path} {reason}: recalculated in LibreOffice first")
    return crankbook.read(path, recalculate=True, progress=progress)


def _export(args):
    import crankbook
    from crankbook.writer.torsion_csv import write, write_trace
    if args.what == "trace":
        source = _stored_results(args.workbook, _progress(args)) if args.workbook \
            else crankbook.compute("thesis")
        path = write_trace(source, args.output)
        print(f"wrote {path}: the cylinder pressure of "
              f"{args.workbook or 'the thesis engine'} (crank angle °, MPa absolute)")
        return 0
    if not args.workbook:
        raise BuildOptionError(f"export {args.what} needs the engine WORKBOOK to read")
    if args.what == "bearing":
        from crankbook.writer import bearing_csv
        path = bearing_csv.write(_stored_results(args.workbook, _progress(args)), args.output)
        print(f"wrote {path}: the journal orbits of the big end and the checked main bearing "
              f"over the second cycle (short-bearing mobility: optimistic at high eccentricity)")
        return 0
    results = _stored_results(args.workbook, _progress(args))
    write(results, args.output, source=args.workbook)
    speed = results.parameters["speed"]
    print(f"wrote {args.output}/stations.csv, harmonics.csv and response.csv (the harmonics "
          f"at {speed:g} r/min; at another speed n the inertia part scales with "
          f"(n/{speed:g})²; the forced response over the workbook's speed sweep)")
    return 0


def _check(args):
    from crankbook.assignment.check import check
    report = check(args.file)
    for line in report.lines:
        print(line)
    return 0 if report.complete else 1


def _grade(args):
    from crankbook.assignment.grade import grade

    from crankbook.assignment.results import words

    started = time.perf_counter()
    summary = grade(args.directory, args.submissions, args.output, feedback=args.feedback,
                    previous=args.previous, keep=args.keep,
                    missing_as_zero=args.missing_as_zero, progress=_progress(args),
                    returns=args.returns, overrides=args.overrides,
                    items=[k.strip() for k in args.items.split(",") if k.strip()]
                    if args.items else None, out_of=args.out_of, lms=args.lms,
                    lms_template=args.lms_template)
    print(words(summary["lang"])["cli_graded"].format(
        seconds=time.perf_counter() - started, **summary))
    return 0


def _presets(args):
    from crankbook.spec import params
    names = params.preset_names()
    if not names:
        raise CrankbookError("no presets found: the installation is missing its templates")
    for name in names:
        preset = params.read_preset(name)["preset"]
        print(f"{name:<22} {preset['en']} / {preset['zh']}")
    return 0


def _parameters(args):
    from crankbook.spec import params
    spec, values, preset = params.load_preset(args.preset)
    if args.group is not None:
        values = params.apply_group(spec, values, preset, args.group)
    for p in spec.parameters:
        value = values[p.key]
        if p.kind == "choice":
            shown = p.choices[int(value) - 1]
        elif p.axis:
            shown = ",".join(f"{v:g}" for v in value)
        else:
            shown = f"{value:g}"
        print(f"{p.key:<34} {shown:>14} {p.unit:<5} {p.en}  [{p.bounds_text()}]")
    return 0


def _terminate(signum, frame):
    raise KeyboardInterrupt


@contextlib.contextmanager
def _warnings_as_lines(said):
    """crankbook's own warnings (a slip such as grams typed for kg) are collected in
    ``said``, one line each, once; the caller prints them after the command's own
    output, or drops them when the command fails (its error is the one line to read).
    A library's (numpy's overflow, xlsxwriter's notes) never reach the user."""

    def show(message, category, *_args, **_kwargs):
        text = _one_line(message)
        if issubclass(category, CrankbookWarning) and text not in said:
            said.append(text)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = show
        yield


def main(argv=None):
    import signal
    signal.signal(signal.SIGTERM, _terminate)      # a kill cleans up like Ctrl-C
    args = _build_parser().parse_args(argv)
    handlers = {"build": _build, "verify": _verify, "audit": _audit, "assign": _assign,
                "grade": _grade, "check": _check, "export": _export, "presets": _presets,
                "parameters": _parameters}
    said = []
    try:
        with _warnings_as_lines(said):
            code = handlers[args.command](args)
        for text in said:
            print(f"crankbook: warning: {text}", file=sys.stderr)
        return code
    except CrankbookError as error:
        shown = error.for_command_line() if isinstance(error, BuildOptionError) else error
        print(f"crankbook: error: {_one_line(shown)}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0
    except KeyboardInterrupt:
        print("crankbook: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
