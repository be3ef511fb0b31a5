"""Reading the values an engine computed from its CSV of each sheet (verify, the
cross-checks): each kind of field reads as the .xlsx reader reads the same cell."""
import pytest

from crankbook.reading.engine_values import ComputedValues, parse_rows
from crankbook.reading.xlsx_reader import Unreadable

FIELDS = [
    # (the engine's field, the value the .xlsx reader gives the cell)
    ("67.5791486372204", 67.5791486372204),
    ("-2.07322731137691E-006", -2.07322731137691e-06),     # LibreOffice's exponent
    ("8.057853e-13", 8.057853e-13),
    ("1E+020", 1e20),
    ("-0", -0.0),
    (".5", 0.5),
    ("", None),                          # an empty cell
    ('""', ""),                          # a formula's empty text (LibreOffice quotes it)
    ('"1"', "1"),                        # text of a number's digits stays text
    ('"1-5-3-6-2-4"', "1-5-3-6-2-4"),
    ('"a, ""b"" and c"', 'a, "b" and c'),
    ('"two\nlines"', "two\nlines"),
    ("#DIV/0!", "#DIV/0!"),              # errors: their text, as .xlsx gives t="e"
    ("Err:502", "Err:502"),
    ("#NUM!", "#NUM!"),
    ("TRUE", True),
    ("FALSE", False),
    ("✗ 连杆过短", "✗ 连杆过短"),
]


@pytest.mark.parametrize("field, value", FIELDS)
def test_a_field_reads_as_the_xlsx_reader_reads_its_cell(field, value):
    (first, got, last), = parse_rows(f"first,{field},last\n")
    assert (first, last) == ("first", "last")
    assert type(got) is type(value) and got == value


@pytest.mark.parametrize("ending", ["\n", "\r\n", "\r"])
def test_rows_end_at_any_line_ending(ending):
    text = ending.join(["1,2", '"x\ny",3', ",", "4"])
    assert parse_rows(text + ending) == parse_rows(text) == \
        [[1.0, 2.0], ["x\ny", 3.0], [None, None], [4.0]]
    assert parse_rows("1,") == [[1.0, None]]


def test_blocks_read_as_the_names_give_them(tmp_path):
    sheet = tmp_path / "00000-参数.csv"
    sheet.write_text('"title"\n1,2,3\n4,5\n', encoding="utf-8")
    values = ComputedValues(tmp_path / "a.xlsx", {"参数": sheet})
    assert values.values("参数", 2, 1, 3, 3) == [1.0, 2.0, 3.0, 4.0, 5.0, None]
    assert values.values("参数", 1, 1, 1, 1) == ["title"]
    assert values.values("参数", 9, 2, 9, 2) == [None]             # past the sheet's end


def test_a_sheet_the_engine_wrote_nothing_for_is_named(tmp_path):
    values = ComputedValues(tmp_path / "a.xlsx", {})
    with pytest.raises(Unreadable, match="no values for sheet 'Torque'"):
        values.values("Torque", 1, 1, 1, 1)


@pytest.mark.parametrize("text", ['1,2"x",3\n', '"open\n', '"a"b\n'])
def test_a_malformed_line_is_refused_with_its_number(text):
    with pytest.raises(Unreadable, match="malformed in line 1"):
        parse_rows(text)
