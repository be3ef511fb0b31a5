"""`crankbook grade`: score returned workbooks against the assigned parameters.

Expected values come from the manifest's parameters through calc (never from cells
a student could edit).  Each submission is read on its own (a bad one is
`unreadable` and costs nobody else); of several files of one student the latest
readable one counts (by modification time, then path) and the notes list the
others.  The results are built in a hidden directory and renamed into place.
"""
import contextlib
import csv
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path


from crankbook.spec import params
from crankbook.spec.evaluate import axis_sizes
from crankbook.assignment import exports, integrity, rounds
from crankbook.assignment.overrides import apply as apply_overrides, read_overrides
from crankbook.assignment import template as templates
from crankbook.assignment.assign import MANIFEST, RUBRIC, SETTINGS
from crankbook.assignment.key import answer_rows, expected, key_results
from crankbook.assignment.results import FEEDBACK_MODES, words, write_results
from crankbook.assignment.scoring import (answer_in, answer_number, pair_positions,
                                          place_rows, score_item)
from crankbook.assignment.submissions import (EngineBudget, convert_foreign, discover,
                                               prepare, read, recalculate)
from crankbook.errors import AssignmentDirError, CrankbookError
from crankbook.support.progress import steps
from crankbook.support.csv_safety import as_typed
from crankbook.support.workspace import (check_output_folder, lock, staged_directory,
                                         sweep_temporary, temporary_directory)

KEEP = ("latest", "best")


@dataclass
class Grade:
    student_id: str
    name: str
    extra: dict = field(default_factory=dict)     # the roster's other columns (班级, …)
    status: str = "missing"                 # graded, missing, unreadable
    items: dict = field(default_factory=dict)     # item key -> (points, [CellResult])
    flags: list = field(default_factory=list)     # tokens: copy-suspect, positions, …
    notes: list = field(default_factory=list)     # (word, fields, private) explaining them
    files: list = field(default_factory=list)
    problem: str = ""
    round: int = 1                          # the round whose work this is
    overrides: list = field(default_factory=list)  # the teacher's decisions applied, in words

    @property
    def score(self):
        return sum(points for points, _ in self.items.values())

    def note(self, flag, word, private=False, **fields):
        """A flag token (None: none) and the words that explain it; ``private`` notes
        name or hint at other students and reach the teacher only."""
        if flag and flag not in self.flags:
            self.flags.append(flag)
        if not any(w == word and f == fields for w, f, _ in self.notes):
            self.notes.append((word, fields, private))


def _listed(names, shown=10):
    """At most ``shown`` names, then how many more."""
    more = f", … (+{len(names) - shown})" if len(names) > shown else ""
    return ", ".join(names[:shown]) + more


def load_directory(directory):
    directory = Path(directory)
    if not (directory / MANIFEST).is_file() or not (directory / SETTINGS).is_file():
        raise AssignmentDirError(f"{directory}: not a directory written by 'crankbook assign' "
                                 f"(no {MANIFEST} or {SETTINGS})")
    try:
        settings = json.loads((directory / SETTINGS).read_text(encoding="utf-8"))
        assignment = templates.load(settings["assignment"], directory / RUBRIC)
        with open(directory / MANIFEST, newline="", encoding="utf-8-sig") as handle:
            roster = [{k: as_typed(v) for k, v in row.items()} for row in csv.DictReader(handle)]
    except (OSError, ValueError, KeyError) as error:
        raise AssignmentDirError(f"{directory}: its {SETTINGS}, {RUBRIC} or {MANIFEST} is "
                                 f"damaged ({type(error).__name__})") from None
    return settings, assignment, roster


def answer_shapes(assignment, lang, spec, values=None):
    """a_ key -> number of cells each answer name must have (``values``: a student's
    parameters, for rows that are items of an axis)."""
    rows = {"positions": len(assignment.positions.labels(lang)) if assignment.positions else 0,
            "crank_angle": len(assignment.grid_angles or ())}
    rows.update({grid: len(angles) for grid, angles in assignment.row_angles.items()})
    if values is not None:
        rows.update(axis_sizes(spec, values))
    else:
        rows.update({axis.key: axis.max for axis in spec.axes})   # the bound, before values
    return {key: 1 if sheet.rows == "scalar" else rows[sheet.rows]
            for sheet in assignment.sheets for key in sheet.items}


def manifest_values(spec, row):
    values = {}
    for p in spec.parameters:
        text = row[f"p_{p.key}"]
        values[p.key] = [float(v) for v in text.strip("[]").split(",")] if p.axis \
            else float(text)
    return params.validate(spec, values)


def grade_submission(sub, manifest_row, assignment, spec, preset, lang, key=None, part=None):
    """(items, problems) of one readable submission (``key``: the student's key
    results, when already computed; ``part``: the items graded, with their points —
    see :func:`part_of` — of the whole ``assignment``)."""
    graded = (part or assignment).item
    values = manifest_values(spec, manifest_row)
    key = key or key_results(assignment, spec, preset, values)
    want = expected(assignment, spec, key)
    rubric = assignment.rubric
    # consequential credit follows the student's whole mechanism: when any upstream
    # answer is off, every upstream answer they gave is used
    given = {}
    for name in rubric.get("upstream", []):
        item = assignment.item.get(name)
        answer = sub.answers.get(name, [None])
        number = answer_in(answer[0], item.unit) if answer and item else None
        if number is not None:
            given[name] = number
    off = any(not math.isclose(number, float(want[name]["value"][0]),
                               rel_tol=assignment.item[name].tolerance,
                               abs_tol=assignment.item[name].abs_floor)
              for name, number in given.items())
    own = expected(assignment, spec, key, overrides=given) if off else None
    labels = answer_rows(assignment, lang, key.results, spec)
    pairing, problems = None, []
    if assignment.positions is not None:
        positions = assignment.positions
        angle_item = positions.angle_item
        own_angles = own[angle_item]["value"] if own is not None else None
        pairing = pair_positions(sub.answers.get(angle_item, []), want[angle_item]["value"],
                                 labels["positions"], positions.match_tolerance, own_angles,
                                 sub.row_labels.get(angle_item))
        problems = pairing.problems
    items = {}
    for sheet in assignment.sheets:
        row_labels = labels.get(sheet.rows) if sheet.rows != "scalar" else None
        rows_of_sheet = pairing.rows if pairing is not None else None
        if sheet.rows == "positions" and pairing is not None:
            rows_of_sheet = _sheet_pairing(sub, sheet, assignment, pairing, row_labels)
        for name in sheet.items:
            item = graded.get(name)
            if item is None:
                continue
            consequential = [own[name]["value"], *own[name]["alternatives"]] \
                if own is not None and item.consequential else []
            answers = sub.answers.get(name, [])
            # placement: the key row each of the file's cells was graded as (annotated
            # returns colour the student's own cells)
            if sheet.rows not in ("scalar", "positions") and name in sub.row_labels:
                rows = place_rows(sub.row_labels[name], row_labels)
                answers = [answers[r] if r is not None and r < len(answers) else None
                           for r in rows]
                sub.placement[name] = _inverse(rows, len(sub.answers.get(name, [])))
            elif sheet.rows == "positions" and rows_of_sheet is not None:
                sub.placement[name] = list(rows_of_sheet)
            else:
                sub.placement[name] = list(range(len(answers)))
            items[name] = score_item(item, rubric, answers, want[name],
                                     [_shown_label(x, sheet.rows in assignment.row_angles)
                                      for x in row_labels] if row_labels else None,
                                     rows_of_sheet if sheet.rows == "positions" else None,
                                     consequential,
                                     pairing.angles if name == getattr(
                                         assignment.positions, "angle_item", None) else None)
    return items, problems


def _shown_label(label, angle):
    """A row's label as the feedback names it: an asked angle as "35°", not "35.0"."""
    if angle and isinstance(label, (int, float)):
        return f"{float(label):g}°"
    return str(label)


def _inverse(rows, count):
    """File row -> key row, from key row -> file row."""
    out = [None] * count
    for key_row, file_row in enumerate(rows):
        if file_row is not None and file_row < count:
            out[file_row] = key_row
    return out


def _sheet_pairing(sub, sheet, assignment, pairing, labels):
    """The key position of each row of one position table.  The crank angles are on one
    table; another table follows the same pairing when its rows carry the same labels,
    else (the student inserted a row in one table only) its rows are placed by label."""
    angle_item = assignment.positions.angle_item
    if angle_item in sheet.items:
        return pairing.rows
    mine = sub.row_labels.get(sheet.items[0])
    theirs = sub.row_labels.get(angle_item)
    if mine is None or mine == theirs:
        return pairing.rows
    where = {str(label).strip(): i for i, label in enumerate(labels)}
    return [where.get(str(label).strip()) if label is not None else None for label in mine]


def choose(subs):
    """The latest readable submission of a student (by modification time, then path),
    or the latest of all when none is readable."""
    readable = [s for s in subs if not s.problem]
    pool = readable or subs
    return max(pool, key=lambda s: (s.mtime, s.relative))


def grade(directory, submissions, output=None, feedback="full", previous=None, keep="latest",
          missing_as_zero=False, progress=None, returns=None, overrides=None, items=None,
          out_of=None, lms="generic", lms_template=None):
    if feedback not in FEEDBACK_MODES:
        raise CrankbookError(f"--feedback {feedback!r}: choose {', '.join(FEEDBACK_MODES)}")
    if keep not in KEEP:
        raise CrankbookError(f"--keep {keep!r}: choose {', '.join(KEEP)}")
    settings, whole, roster = load_directory(directory)
    assignment = part_of(whole, items, out_of)
    decisions = read_overrides(overrides, {r["student_id"] for r in roster},
                               {k: i.points for k, i in assignment.item.items()}) \
        if overrides else []
    exports.check_lms(lms, lms_template, roster)
    lang = settings.get("lang", "zh")
    spec, _, preset = params.load_preset(settings["preset"])
    root = Path(submissions)
    if not root.is_dir():
        raise CrankbookError(f"{root}: no such folder of submissions")
    output = output if output is not None else Path(directory) / "results"
    inputs = [(directory, True), (Path(directory) / "students", False),
              (Path(directory) / "keys", False), (root, False), (overrides, False),
              (lms_template, False), (previous, False)]
    output = check_output_folder(output, "grade", inputs)
    returns = check_output_folder(returns, "grade --return", [*inputs, (output, False)],
                                  "--return") if returns is not None else None
    # a second run into the same results or returns is refused now, before the work
    with lock(output), (lock(returns) if returns is not None else contextlib.nullcontext()):
        return _grade(assignment, roster, lang, spec, preset, root, output, feedback,
                      previous, keep, missing_as_zero, progress, returns,
                      RunOptions(whole, decisions, lms, lms_template,
                                 Path(directory) / "students"))


def part_of(assignment, items=None, out_of=None):
    """The assignment graded this time: only ``items`` (a_ keys or keys; None: all), every
    item's points scaled so that the total is ``out_of`` (None: as written)."""
    import dataclasses
    chosen = assignment.items
    if items:
        wanted = [k[2:] if k.startswith("a_") else k for k in items]
        unknown = [k for k in wanted if k not in assignment.item]
        if unknown:
            raise CrankbookError(f"--items: {', '.join(unknown)} is not an item of "
                                 f"{assignment.key}; items are "
                                 f"{', '.join(i.key for i in assignment.items)}")
        chosen = [i for i in assignment.items if i.key in wanted]
    total = sum(i.points for i in chosen)
    if out_of is not None and not (out_of > 0 and math.isfinite(out_of)):
        raise CrankbookError(f"--out-of {out_of:g}: must be a positive number")
    factor = out_of / total if out_of is not None and total else 1.0
    chosen = [dataclasses.replace(i, points=i.points * factor) for i in chosen]
    keys = {i.key for i in chosen}
    sheets = [dataclasses.replace(s, items=tuple(k for k in s.items if k in keys))
              for s in assignment.sheets]
    return dataclasses.replace(assignment, items=chosen, sheets=[s for s in sheets if s.items])


@dataclass(frozen=True)
class RunOptions:
    """What a grading run carries beside the graded part of the assignment: the whole
    assignment (answer shapes, keys and copying are judged on the whole file), the
    teacher's override decisions and the LMS export."""
    whole: object
    decisions: list = field(default_factory=list)
    lms: str = "generic"
    lms_template: object = None
    assigned: object = None        # the class folder's students/: returns are built on them


def _grade(assignment, roster, lang, spec, preset, root, output, feedback, previous, keep,
           missing_as_zero, progress, returns, options):
    sweep_temporary()                  # scratch copies and engines of killed runs
    w = words(lang)
    earlier, earlier_suspicions = rounds.load(previous, assignment) if previous else ({}, [])

    shapes = answer_shapes(options.whole, lang, spec)   # every answer: positions need angles
    # zips unpacked and .ods/.xls/.et converted in a private scratch folder, gone after
    with temporary_directory("unpack") as scratch:
        subs = prepare(discover(root), root, scratch)
        # one LibreOffice budget for the whole run: converting and recalculating share it
        budget = EngineBudget()
        convert_foreign(subs, scratch, progress, w["progress_converting"], budget)
        for sub in steps(subs, w["progress_reading"], progress=progress):
            if not sub.problem and not sub.needs_conversion:
                read(sub, shapes)
        recalculate(subs, shapes, progress, w["progress_recalculating"], budget)

    by_id = {row["student_id"]: row for row in roster}
    _match(subs, by_id)
    extra = [f for f in (roster[0] if roster else {}) if f not in ("student_id", "name",
                                                                     "fingerprint")
             and not f.startswith("p_")]
    grades = {sid: Grade(student_id=sid, name=row["name"],
                         extra={f: row.get(f, "") for f in extra}) for sid, row in by_id.items()}
    keys = _Keys(options.whole, spec, preset, by_id)
    mine = {}
    for sub in subs:
        if sub.student_id in grades:
            mine.setdefault(sub.student_id, []).append(sub)
    chosen = {}
    for sid, files in mine.items():
        g = grades[sid]
        g.files = [s.relative for s in files]
        sub = chosen[sid] = choose(files)
        if len(files) > 1:
            g.note("multiple-submissions", "multiple", private=True, count=len(files),
                   chosen=sub.relative, others=_listed([s.relative for s in files
                                                        if s is not sub]))
        named = sorted({i for s in files for i in s.other_ids})
        if named:                       # an upload named for someone else stays its owner's
            g.note("path-names-other", "path_names_other", private=True,
                   others=", ".join(named))
        if sub.problem:
            g.status, g.problem = "unreadable", sub.problem
            if sub.is_key:
                g.note("leaked-key", "leaked_key", private=True,
                       whose=_whose_parameters(sub, by_id, spec) or "?")
            continue
        try:
            g.items, problems = grade_submission(sub, by_id[sid], options.whole, spec,
                                                 preset, lang, keys.results(sid),
                                                 part=assignment)
        except Exception as error:          # one student's file must not stop the class
            g.status, g.problem = "unreadable", f"could not be graded ({type(error).__name__})"
            continue
        g.status = "graded"
        for word, fields in problems:
            g.note("positions", word, **fields)
        edited = _rows_edited(sub, answer_shapes(options.whole, lang, spec,
                                                 manifest_values(spec, by_id[sid])))
        if edited:
            g.note("rows-edited", "rows_edited", count=edited)
        _flag(g, sub, by_id, spec, lang)
    graded = {sid: sub for sid, sub in chosen.items() if grades[sid].status == "graded"}
    whole = options.whole          # copying is judged on the whole file
    suspicions = integrity.find(grades, graded, {sid: integrity.numeric_answers(sub, whole)
                                                 for sid, sub in graded.items()},
                                keys.all_expected(), whole)
    for suspicion in suspicions:
        g = grades[suspicion.who]
        for kind in suspicion.kinds:
            if kind == "wrong_student_file":
                g.note("wrong-student", "wrong_student", private=True, other=suspicion.whom)
            g.note("copy-suspect", f"suspect_{kind}", private=True, other=suspicion.whom or "")
    this_round = dict(grades)
    for sid in grades:
        grades[sid] = rounds.keep(grades[sid], earlier.get(sid), keep)
    suspicions = rounds.kept_suspicions(grades, this_round, earlier, suspicions,
                                        earlier_suspicions)
    for suspicion in suspicions:          # an earlier round's, for a resubmitted grade
        if suspicion.evidence.get("from_round"):
            grades[suspicion.who].note("copy-suspect", "suspect_from_round", private=True,
                                       round=suspicion.evidence["from_round"],
                                       other=suspicion.whom or "")
    apply_overrides(grades, options.decisions, assignment)
    unmatched = [s for s in subs if s.student_id not in grades]
    # the returns first: a student whose workbook cannot go back is told why in the
    # gradebook and every feedback; both folders replace the old ones only when whole
    back = staged_directory(returns, replace=True, command="grade --return") \
        if returns is not None else contextlib.nullcontext()
    with back as back_staging:
        if back_staging is not None:
            from crankbook.assignment.annotate import write_returns
            write_returns(back_staging, assignment, lang, list(grades.values()),
                          # a grade kept from an earlier round is not this file's
                          {sid: sub for sid, sub in chosen.items()
                           if grades[sid] is this_round[sid]}, feedback, options.assigned)
        with staged_directory(output, replace=True, command="grade") as staging:
            write_results(staging, assignment, spec, lang, list(grades.values()), unmatched,
                          feedback=feedback, missing_as_zero=missing_as_zero,
                          suspicions=suspicions)
            exports.write_lms(staging, options.lms, options.lms_template, assignment, lang,
                              list(grades.values()), feedback, missing_as_zero)
    return {"graded": sum(g.status == "graded" for g in grades.values()),
            "missing": sum(g.status == "missing" for g in grades.values()),
            "unreadable": sum(g.status == "unreadable" for g in grades.values()),
            "roster": len(grades), "unmatched": len(unmatched), "suspicions": len(suspicions),
            "output": str(output), "lang": lang}


def _rows_edited(sub, shapes):
    """Rows the student added to or removed from the answer tables (the largest change
    of any one table: its columns move together)."""
    return max((abs(len(values) - shapes[key]) for key, values in sub.answers.items()
                if key in shapes and shapes[key] > 1), default=0)


class _Keys:
    """Each roster student's key, computed once: for their own grade and for holding
    every file against every key (the integrity check)."""

    def __init__(self, assignment, spec, preset, by_id):
        self.assignment, self.spec, self.preset, self.by_id = assignment, spec, preset, by_id
        self._results, self._expected = {}, {}

    def results(self, sid):
        if sid not in self._results:
            values = manifest_values(self.spec, self.by_id[sid])
            self._results[sid] = key_results(self.assignment, self.spec, self.preset, values)
        return self._results[sid]

    def all_expected(self):
        for sid in self.by_id:
            if sid not in self._expected:
                try:
                    self._expected[sid] = expected(self.assignment, self.spec, self.results(sid))
                except CrankbookError:
                    continue
        return self._expected


MOODLE_FOLDER = re.compile(r"^(?P<name>.+?)_(?P<participant>\d+)_assignsubmission_[a-z]+_?$")


def _match(subs, by_id):
    """The roster student of each file: the outermost part of its path that names one
    (the student's LMS folder; the file name where there are no folders).  A Moodle
    download folder (``Full Name_1234567_assignsubmission_file_``) is matched by the
    participant's full name, Moodle's number being no roster id.  Nothing inside a
    file, and no deeper folder or file name, can make it another student's: they are
    only noted (``other_ids``) for the teacher.  A part that names two students — two
    ids, even one inside the other, or a name two students share — leaves the file
    unmatched (``ambiguous``), listed for the teacher."""
    from pathlib import PurePath
    patterns = [(re.compile(rf"(?<![A-Za-z0-9]){re.escape(i)}(?![A-Za-z0-9])"), i)
                for i in by_id]
    by_name = {}
    for sid, row in by_id.items():
        by_name.setdefault(_plain_name(row.get("name", "")), []).append(sid)
    for sub in subs:
        sub.student_id, sub.other_ids, sub.ambiguous = None, [], []
        parts = list(PurePath(sub.relative).parts)
        parts[-1] = PurePath(parts[-1]).stem
        for depth, part in enumerate(parts):
            moodle = MOODLE_FOLDER.match(part)
            if moodle:
                ids = sorted(by_name.get(_plain_name(moodle.group("name")), []))
                if not ids:
                    break                   # a participant not on the roster: unmatched
            else:
                ids = _ids_in(part, patterns)
            if len(ids) > 1:
                sub.ambiguous = ids
                break
            if ids:
                sub.student_id = ids[0]
                sub.other_ids = sorted({i for deeper in parts[depth + 1:]
                                        for i in _ids_in(deeper, patterns)} - {ids[0]})
                break


def _plain_name(name):
    """A name compared as people write it: case, width and spacing aside."""
    import unicodedata
    return " ".join(unicodedata.normalize("NFKC", str(name)).casefold().split())


def _ids_in(text, patterns):
    """The roster ids ``text`` names, each standing alone (s1 is not named by s10);
    an id inside another named id (s1 in s1-2) counts too, so such a part names two."""
    return sorted({i for pattern, i in patterns if pattern.search(text)})


def _whose_parameters(sub, by_id, spec):
    """The roster student whose assigned parameters a file's p_ cells hold (nine in
    ten of them at least, and no one else as many), or None."""
    have = {}
    for parameter in spec.scalar_parameters():
        if parameter.key in sub.parameters:
            try:                              # a choice's word, or a number
                have[parameter.key] = params.coerce(parameter, sub.parameters[parameter.key])
            except CrankbookError:
                have[parameter.key] = answer_number(sub.parameters[parameter.key])
    have = {k: v for k, v in have.items() if v is not None}
    if not have:
        return None
    # a key sets an input or two of its own (the given pressure trace): the student
    # whose parameters it holds is the one it matches best, nearly everywhere, alone
    matches = {sid: sum(abs(v - float(row[f"p_{k}"])) <= 1e-9 * max(1.0, abs(float(
        row[f"p_{k}"]))) for k, v in have.items()) for sid, row in by_id.items()}
    best = max(matches.values(), default=0)
    winners = [sid for sid, n in matches.items() if n == best]
    return winners[0] if len(winners) == 1 and best >= 0.9 * len(have) else None


def _flag(g, sub, by_id, spec, lang="en"):
    assigned = by_id[g.student_id]
    changed = []
    for parameter in spec.scalar_parameters():
        if parameter.key not in sub.parameters:
            continue
        try:                                  # a choice's word, or a number
            have = params.coerce(parameter, sub.parameters[parameter.key])
        except CrankbookError:
            have = answer_number(sub.parameters[parameter.key])
        want = float(assigned[f"p_{parameter.key}"])
        if have is None or abs(have - want) > 1e-9 * max(1.0, abs(want)):
            changed.append(parameter)
    if changed:
        # named as the Task sheet describes them, with the key the cell is named by
        named = [f"{p.zh}（p_{p.key}）" if lang == "zh" else f"{p.en} (p_{p.key})"
                 for p in changed]
        g.note("parameters-changed", "parameters_changed",
               keys=("、" if lang == "zh" else ", ").join(named))
        for sid, row in by_id.items():
            if sid != g.student_id and all(
                    answer_number(sub.parameters.get(p.key)) is not None and
                    abs(answer_number(sub.parameters[p.key]) - float(row[f"p_{p.key}"])) <=
                    1e-9 * max(1.0, abs(float(row[f"p_{p.key}"])))
                    for p in spec.scalar_parameters() if p.key in sub.parameters):
                g.note("wrong-student", "parameters_of", private=True, other=sid)
                break
    if all(c.reason == "no_answer" for _, cells in g.items.values() for c in cells):
        g.note("blank", "blank")
