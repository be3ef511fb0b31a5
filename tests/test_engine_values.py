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


def _renamed_sheet(source, target, name):
    """``source`` saved as ``target`` with its first sheet renamed ``name`` in
    workbook.xml (Excel, LibreOffice and xlsxwriter refuse such a name; a hand-made
    file need not)."""
    import re
    import zipfile
    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item)
            if item.filename == "xl/workbook.xml":
                data = re.sub(rb'(<sheet [^>]*?name=")[^"]*"',
                              lambda match: match.group(1) + name + b'"', data, count=1)
            zout.writestr(item, data)


def test_a_sheet_name_that_would_be_a_path_is_refused_before_any_engine(tmp_path, ssconvert):
    """Each sheet's values are written to <file>-<sheet>.csv, and Gnumeric resolves a
    '..' in that name: a sheet named '../../../x' put x.csv outside the scratch folder.
    A sheet name Excel would not allow is refused in one line, the engine never run."""
    import crankbook
    from tests.conftest import run_cli
    built = crankbook.compute("offset-optimization").to_excel(tmp_path / "o.xlsx")
    work = tmp_path / "deep" / "er"
    work.mkdir(parents=True)
    for number, name in enumerate([b"../../../x", b"a\\b", b"a:b"]):
        hostile = work / f"h{number}.xlsx"
        _renamed_sheet(built, hostile, name)
        for command in (["verify", hostile, "--engine", "gnumeric"], ["audit", hostile]):
            done = run_cli(*command)
            assert done.returncode == 2, (command, done.stdout, done.stderr)
            assert "not one Excel allows" in done.stderr and "Traceback" not in done.stderr
            assert len(done.stderr.strip().splitlines()) == 1, done.stderr
        with pytest.raises(crankbook.errors.CrankbookError, match="not one Excel allows"):
            crankbook.read(hostile, recalculate=True)
    assert not list(tmp_path.rglob("x.csv")) and not list(tmp_path.rglob("*.csv"))


def test_a_libreoffice_that_writes_one_sheet_saves_the_workbook_instead(tmp_path, soffice,
                                                                         monkeypatch):
    """LibreOffice before 7.2 has no 'every sheet' in its CSV filter and writes the
    first sheet only, as <file>.csv: its values are then read from the workbook it
    saves back, and verify agrees as it did before it asked for CSV."""
    import crankbook
    from crankbook.reading import recalc
    path = crankbook.compute("offset-optimization").to_excel(tmp_path / "o.xlsx")
    monkeypatch.setattr(recalc, "LIBREOFFICE_CSV", recalc.LIBREOFFICE_CSV.rsplit(",", 1)[0])
    values, = recalc.computed_values([path], tmp_path / "lo")
    assert values.path == path and not list((tmp_path / "lo").glob("*-*.csv"))
    frame = crankbook.verify(path)
    assert frame["ok"].all() and frame.attrs["valid"] == 1


def test_two_files_of_one_name_keep_their_own_values(tmp_path, soffice):
    """An engine names each sheet's CSV after its workbook: two o.xlsx from two folders
    are computed from numbered copies, so neither reads the other's values."""
    import crankbook
    from crankbook.reading import recalc
    from tests.conftest import named_computed
    paths = []
    for folder, speed in (("a", 2000.0), ("b", 4000.0)):
        (tmp_path / folder).mkdir()
        paths.append(crankbook.compute("thesis", step=6.0, speed=speed).to_excel(
            tmp_path / folder / "o.xlsx"))
    computed = recalc.computed_values(paths, tmp_path / "lo")
    speeds = [named_computed(p, v)["q_angular_velocity"] for p, v in zip(paths, computed)]
    assert speeds == pytest.approx([2000 * 3.141592653589793 / 30, 4000 * 3.141592653589793 / 30])
