"""`assign --groups [FILE]`: the guide's group table drives the class.

Each roster row names its group in a ``组号`` / ``group`` column; every student of a
group gets the group's values (the guide's 附表1 — the preset's group table — or
the teacher's own table, FILE: a CSV as Excel saves it, or a TOML like
``templates/groups/``, one row per group with ``number`` / ``组号`` and parameter
keys in the workbook's units).  What the table does not set — the valve train, the
cams — is still drawn per student, so group-mates share a mechanism but not every
answer.
"""
import csv
import io
import tomllib
from pathlib import Path

from crankbook.spec import params

from crankbook.support import resources
from crankbook.assignment.roster import excel_text
from crankbook.errors import RosterError, UnknownGroupError
from crankbook.support.paths import require_file

GROUP_COLUMNS = ("组号", "group", "小组", "组", "group number")
NUMBER_COLUMNS = ("number", "组号", "group")


def roster_groups(rows):
    """student_id -> group number, from the roster's group column."""
    fields = list(rows[0]) if rows else []
    column = next((f for f in fields if f.strip().lower() in GROUP_COLUMNS), None)
    if column is None:
        raise RosterError("assign --groups: the roster needs a group column (组号 or group)")
    out = {}
    for number, row in enumerate(rows, start=2):
        text = str(row.get(column, "")).strip()
        try:
            value = float(text)
            if not value.is_integer():
                raise ValueError
        except ValueError:
            raise RosterError(f"roster row {number}: group {text!r} of {row['student_id']} is "
                              f"not a whole number") from None
        out[row["student_id"]] = int(value)
    return out


def group_table(spec, preset, source):
    """group number -> {parameter key: value} from the preset's table ("preset") or a
    teacher's file."""
    if source == "preset":
        table = preset.get("groups")
        if table is None:
            raise UnknownGroupError(f"assign --groups: preset {preset['name']!r} has no table "
                                    f"of groups; give one as --groups FILE")
        entries = resources.read_toml(params.GROUPS, f"{table}.toml")["group"]
        where = f"{params.GROUPS}/{table}.toml"
    else:
        entries, where = _teachers_table(Path(source)), str(source)
    out = {}
    for entry in entries:
        entry = dict(entry)
        number = next((entry.pop(k) for k in NUMBER_COLUMNS if k in entry), None)
        try:
            number = int(float(number))
        except (TypeError, ValueError):
            raise UnknownGroupError(f"groups {where}: a row without a group number "
                                    f"(column number or 组号)") from None
        values = {}
        for key, value in entry.items():
            if value in ("", None):
                continue
            if key not in spec.parameter:
                raise UnknownGroupError(f"groups {where}, group {number}: {key!r} is not a "
                                        f"parameter of this workbook")
            values[key] = params.coerce(spec.parameter[key], value, f"group {number}")
        out[number] = values
    return out


def _teachers_table(path):
    require_file(path, UnknownGroupError, "--groups")
    data = path.read_bytes()[:2_000_000]
    if path.suffix.lower() == ".toml":
        try:
            return tomllib.loads(data.decode("utf-8"))["group"]
        except (UnicodeDecodeError, tomllib.TOMLDecodeError, KeyError) as error:
            raise UnknownGroupError(f"--groups {path}: not a table of [[group]] rows "
                                    f"({type(error).__name__})") from None
    text = excel_text(data, f"--groups {path}", UnknownGroupError)
    rows = list(csv.DictReader(io.StringIO(text)))
    return [{k.strip(): (v or "").strip() for k, v in row.items() if k} for row in rows]


def fixed_values(spec, preset, source, rows):
    """student_id -> the values of their group (for variants.draw_class)."""
    table = group_table(spec, preset, source)
    out = {}
    for sid, number in roster_groups(rows).items():
        if number not in table:
            raise UnknownGroupError(f"assign --groups: {sid} is in group {number}, which the "
                                    f"table does not have (groups {min(table)}–{max(table)})")
        out[sid] = table[number]
    return out
