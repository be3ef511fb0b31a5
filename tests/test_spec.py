"""The specification language (docs/templates.md) and the named-range contract.

Spec-authoring mistakes must raise a SpecError naming the file and the key; each
placeholder must compile to the Excel text docs/templates.md says; the shipped templates
must keep the contract and write every formula once."""
import collections
import re
from pathlib import Path

import numpy as np
import pytest

from crankbook.spec import evaluate

from crankbook.spec import params

from crankbook.spec import placeholders

from crankbook.support import resources
from crankbook.errors import SpecError
from crankbook.spec.formulas import Context, Locator, Place
from crankbook.reading.pressure_file import close_cycle
from crankbook.spec.loader import from_data, load, template_names
from tests.conftest import named, run_cli

CONTRACT = {  # issue 3: q_ names and their units
    "crank_angle": "deg", "piston_displacement": "mm", "piston_velocity": "m/s",
    "piston_acceleration": "m/s²", "rod_angle": "deg", "cylinder_pressure": "MPa",
    "gas_force": "N", "inertia_force": "N", "piston_force": "N", "side_force": "N",
    "rod_force": "N", "tangential_force": "N", "radial_force": "N", "torque": "N·m",
}
PARAMETERS = {
    "crank_radius": "mm", "rod_length": "mm", "offset": "mm", "bore": "mm", "speed": "rpm",
    "piston_mass": "kg", "rod_mass": "kg", "rod_cg_from_big_end": "mm",
    "crank_unbalanced_mass": "kg", "ambient_pressure": "MPa", "exact_kinematics": "-",
}
CELL_LIKE = re.compile(r"^([A-Za-z]{1,3}\d+|[Rr]\d*[Cc]\d*|[RrCc])$")


def test_contract_keys_and_units():
    spec = load("engine")
    for key, unit in CONTRACT.items():
        assert spec.unit_of(key) == unit, key
    for key, unit in PARAMETERS.items():
        assert spec.parameter[key].unit == unit, key


@pytest.mark.parametrize("name", template_names())
def test_every_quantity_has_labels_formula_and_calc(name):
    spec = load(name)
    for q in spec.quantities():
        if q.is_numeric_grid:
            continue
        assert q.zh and q.en and q.calc, q.key
        assert q.formula or q.kind == "scalar", q.key       # decision cells have none
        q.calc_function()


def test_defined_names_are_valid_and_complete(tmp_path):
    path = tmp_path / "t.xlsx"
    assert run_cli("build", "--step", "10", "-o", path).returncode == 0
    names = named(path)
    spec = load("engine")
    expected = {f"p_{k}" for k in spec.parameter} | {f"p_{k}" for k in spec.table_column} | \
        {f"q_{q.key}" for q in spec.quantities()}
    assert expected <= set(names)
    for name in names:
        assert re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.]*", name) and not CELL_LIKE.match(name)
    assert len(names["q_torque"]) == 73


@pytest.mark.parametrize("preset", ["thesis", "course-design", "compressor",    # each template
                                    "offset-optimization"])
@pytest.mark.parametrize("lang", ["zh", "en"])
def test_no_chart_hides_a_cell_and_no_text_is_cut(tmp_path, preset, lang):
    """A chart anchored over a table or a chart frame's cells hides them; a text
    wider than its column is stopped by a value beside it ('stroke_study_swept_volume_alt',
    'Section / mode 1')."""
    from crankbook import compute
    from tests.conftest import cells_under_charts, texts_cut_by_a_neighbour
    step = None if preset == "offset-optimization" else 30         # the layout, not the grid
    coarse = {"cam_step": 30} if preset == "course-design" else {}
    path = compute(preset, step=step, **coarse).to_excel(tmp_path / "t.xlsx", lang=lang)
    assert not cells_under_charts(path)
    assert not texts_cut_by_a_neighbour(path)


def test_cells_beside_wrapped_text_stand_on_its_first_line(tmp_path):
    """In a row made tall by a wrapped description every cell is top-aligned: a value
    at the bottom reads as the next row's (the Summary's 'Mean torque per cylinder')."""
    import openpyxl
    from crankbook import compute
    path = compute("v8-crossplane", step=10).to_excel(tmp_path / "t.xlsx", lang="en")
    book, low = openpyxl.load_workbook(path), []
    for ws in book.worksheets:
        for row, dimension in ws.row_dimensions.items():
            if dimension.height is None or dimension.height <= 16 or \
                    not any(ws.cell(row, c).alignment.wrap_text for c in range(1, 8)):
                continue
            low += [(ws.title, cell.coordinate) for cell in ws[row]
                    if cell.value not in (None, "") and cell.alignment.vertical not in ("top", "center")
                    and not ws.cell(row, 1).font.sz == 14]          # a title row
    assert not low, low[:8]


def test_each_formula_is_written_once():
    """No formula text of a workbook template or library appears twice (they are
    placed from templates/common instead)."""
    seen = collections.defaultdict(list)

    def walk(node, file):
        if isinstance(node, dict):
            for key, value in node.items():
                if key in ("formula", "first") and isinstance(value, str) and len(value) > 12:
                    seen[value].append((file, node.get("key")))
                walk(value, file)
        elif isinstance(node, list):
            for value in node:
                walk(value, file)
    files = [f"{n}.toml" for n in template_names()] + \
        [f"common/{n}.toml" for n in resources.names("common")]
    for file in files:
        walk(resources.read_toml(*file.split("/")), file)
    copies = {text: where for text, where in seen.items() if len(where) > 1}
    assert not copies, copies


# ---------------------------------------------------------------- authoring mistakes
def _minimal(**extra):
    data = {
        "workbook": {"key": "t", "zh": "t", "en": "t", "grid": "angle", "cycle": 360.0,
                     "grid_step": 30.0},
        "groups": {"g": {"zh": "g", "en": "g"}},
        "parameter": [{"key": "crank_radius", "group": "g", "unit": "mm", "zh": "r", "en": "r",
                       "default": 50.0, "min": 0.0, "min_open": True}],
        "sheet": [{"key": "s", "zh": "s", "en": "s", "column": [
            {"key": "x", "unit": "mm", "zh": "x", "en": "x",
             "formula": "{crank_radius}*(1-COS({angle|rad}))",
             "calc": "calc.kinematics.piston_displacement_first_order",
             "args": {"crank_angle": "angle"}}]}],
    }
    for section, value in extra.items():
        data[section] = value
    return data


def _with_column(**column):
    data = _minimal()
    data["sheet"][0]["column"].append({"key": "y", "unit": "mm", "zh": "y", "en": "y",
                                       "calc": "calc.kinematics.piston_displacement_first_order",
                                       "args": {"crank_angle": "angle"}, **column})
    return data


def test_a_minimal_template_loads_and_evaluates():
    spec = from_data(_minimal())
    out = evaluate.evaluate(spec, {"crank_radius": 50.0})
    assert np.allclose(out["x"], 50 * (1 - np.cos(np.radians(np.arange(0, 361, 30)))))


@pytest.mark.parametrize("column,words", [
    ({"formula": "{no_such_key}*2"}, "refers to unknown 'no_such_key'"),
    ({"formula": "OFFSET({x},1,0)"}, "uses OFFSET"),
    ({"formula": "INDIRECT(\"A1\")"}, "uses INDIRECT"),
    ({"formula": "{x|kg}"}, "cannot convert mm to kg"),
    ({"formula": "{x:bogus}"}, "unknown part 'bogus'"),
    ({"formula": "{x:at(90}"}, "unmatched '}'"),
    ({"formula": "{item}"}, "{item} outside a per-item quantity"),
    ({"formula": "{sum:cylinder({x})}"}, "unknown axis"),
    ({"formula": "{x}", "calc": "calc.kinematics.no_such_function"}, "not a function"),
    ({"formula": "{x}", "unit": "furlong"}, "unit 'furlong'"),
    ({"formula": "{x:items}"}, "needs a per-item quantity"),
    ({"formula": "-{x}^2"}, "unary minus before '^'"),
    ({"formula": "1+(-({x}*2)^2)"}, "unary minus before '^'"),
    ({"formula": "MAX(0,-SQRT({x})^3)"}, "unary minus before '^'"),
])
def test_authoring_mistakes_name_the_file_and_key(column, words):
    with pytest.raises(SpecError) as caught:
        from_data(_with_column(**column), file="mine.toml")
    message = str(caught.value)
    assert message.startswith("templates/mine.toml: y: "), message
    assert words in message
    assert caught.value.file == "mine.toml" and caught.value.key == "y"


def _repeated(**repeat_fields):
    """A template whose y1, y2, y3 are one repeated column, each from the one before."""
    data = _minimal()
    data["sheet"][0]["column"].append({
        "repeat": {"n": [1, 2, 3], "before": ["x", "y1", "y2"]}, "key": "y${n}", "unit": "mm",
        "zh": "y${n}", "en": "step ${n}", "formula": "{${before}}+${n}",
        "calc": "calc.kinematics.piston_displacement_first_order",
        "args": {"crank_angle": "angle"}, **repeat_fields})
    return data


def test_a_repeated_entry_is_its_written_out_copies():
    written = _minimal()
    for n, before in ((1, "x"), (2, "y1"), (3, "y2")):
        written["sheet"][0]["column"].append({
            "key": f"y{n}", "unit": "mm", "zh": f"y{n}", "en": f"step {n}",
            "formula": f"{{{before}}}+{n}",
            "calc": "calc.kinematics.piston_displacement_first_order",
            "args": {"crank_angle": "angle"}})
    assert from_data(_repeated()) == from_data(written)


@pytest.mark.parametrize("fields,words", [
    ({"repeat": {"n": [1, 2], "before": ["x"]}}, "the lists must be of one length"),
    ({"repeat": {"n": []}}, "n must be a list of numbers or words"),
    ({"repeat": {"N": [1]}}, "'N' is not a plain lower-case name"),
    ({"repeat": [1, 2]}, "repeat must be a table of lists"),
    ({"repeat": {"n": [1, 2, 3], "before": ["x", "y1", "y2"]}, "zh": "${m}"},
     "${m} is not one of the repeat's names"),
])
def test_a_malformed_repeat_names_the_file_and_entry(fields, words):
    with pytest.raises(SpecError) as caught:
        from_data(_repeated(**fields), file="mine.toml")
    assert str(caught.value).startswith("templates/mine.toml: y${n}: ")
    assert words in str(caught.value)


def test_together_repeats_a_block_of_entries_in_order():
    """Two entries per value, value after value: a1, b1, a2, b2 — as written out."""
    def column(key, formula, **extra):
        return {"key": key, "unit": "mm", "zh": key, "en": key, "formula": formula,
                "calc": "calc.kinematics.piston_displacement_first_order",
                "args": {"crank_angle": "angle"}, **extra}
    repeated = _minimal()
    repeated["sheet"][0]["column"] += [
        column("a${n}", "{x}*${n}", repeat={"n": [1, 2]}, together=2),
        column("b${n}", "{a${n}}+1")]
    written = _minimal()
    written["sheet"][0]["column"] += [column("a1", "{x}*1"), column("b1", "{a1}+1"),
                                      column("a2", "{x}*2"), column("b2", "{a2}+1")]
    spec = from_data(repeated)
    assert [q.key for q in spec.quantities()][2:] == ["a1", "b1", "a2", "b2"]
    assert spec == from_data(written)


@pytest.mark.parametrize("together,after,words", [
    (3, [], "together = 3, but only 1 entries follow from here"),
    (0, [], "together must be a whole number of entries"),
    (2, [{"repeat": {"n": [1]}}], "has no repeat or together of its own"),
])
def test_a_malformed_together_names_the_file_and_entry(together, after, words):
    data = _repeated(together=together)
    data["sheet"][0]["column"] += [{"key": "z", "unit": "mm", "zh": "z", "en": "z",
                                    "formula": "{x}", **extra} for extra in after]
    with pytest.raises(SpecError) as caught:
        from_data(data, file="mine.toml")
    assert str(caught.value).startswith("templates/mine.toml: y${n}: ")
    assert words in str(caught.value)


def test_a_repeat_name_outside_a_repeated_entry_is_refused():
    with pytest.raises(SpecError, match=r"mine.toml: repeat: \$\{n\} is used outside"):
        from_data(_with_column(formula="{x}*${n}"), file="mine.toml")


@pytest.mark.parametrize("formula", ["-({x}^2)", "0-{x}^2", "{x}-{x}^2", "2^-{x}",
                                     "{x}*-1", "EXP(-{x})^2"])
def test_a_minus_a_spreadsheet_reads_as_numpy_does_is_allowed(formula):
    from_data(_with_column(formula=formula), file="mine.toml")


def test_a_key_defined_twice_is_refused():
    data = _with_column(formula="{x}")
    data["sheet"][0]["column"][1]["key"] = "x"
    with pytest.raises(SpecError, match="x: defined twice"):
        from_data(data)


def test_a_rule_on_a_guarded_quantity_would_be_circular():
    data = _minimal(rule=[{"key": "too_big", "formula": "MAX({x})>100", "names": ["crank_radius"],
                           "calc": "calc.checks.not_positive", "args": {"value": "x"},
                           "zh": "z", "en": "e"}])
    with pytest.raises(SpecError, match="check_too_big: depends on 'x', which is guarded"):
        from_data(data)


def test_unknown_column_set_and_rulebook_entry():
    data = _minimal()
    data["sheet"][0]["use"] = [{"columnset": "nope"}]
    with pytest.raises(SpecError, match="nope: unknown column set"):
        from_data(data)
    data = _minimal(rule=[{"from": "nope"}])
    with pytest.raises(SpecError, match="nope: no such rule in the rulebooks"):
        from_data(data)


@pytest.mark.parametrize("curves", [0, -1, 2.5, "3"])
def test_a_charts_curve_count_is_a_whole_number(curves):
    data = _minimal()
    data["sheet"][0]["charts"] = [{"y": ["x"], "curves": curves}]
    with pytest.raises(SpecError, match="s: chart: curves must be a whole number"):
        from_data(data)


@pytest.mark.parametrize("rows_from", ["0", True, [0.0]])
def test_a_charts_first_row_is_a_grid_value(rows_from):
    data = _minimal()
    data["sheet"][0]["charts"] = [{"y": ["x"], "rows_from": rows_from}]
    with pytest.raises(SpecError, match="s: chart: rows_from must be a value of the sheet's grid"):
        from_data(data)


@pytest.mark.parametrize("extra", [{}, {"axis": "cylinder", "default": [1.0, 2.0]},
                                   {"axis": "cylinder", "default": 1.0}])
def test_a_fill_parameter_has_an_axis_and_one_value(extra):
    data = _minimal()
    data["parameter"].append({"key": "z", "group": "g", "unit": "mm", "zh": "z", "en": "z",
                              "default": 1.0, "fill": True, **extra})
    with pytest.raises(SpecError, match="z: fill = true needs an axis and a one-value default"):
        from_data(data)


# ---------------------------------------------------------------- the placeholders
def test_placeholders_parse_and_unparse():
    text = ('IF({x}<{item},{sum:cylinder(IF({throw}<{item},{torque:items},0))},'
            '{torque:at({crank_angle}-{firing_angle|deg}+360)})+{a:head|m}+"{not a ref}"')
    nodes = placeholders.parse(text)
    assert placeholders.unparse(nodes) == text
    assert placeholders.references(text) == ["x", "throw", "torque", "torque", "crank_angle",
                                             "firing_angle", "a"]


def _locator():
    """A layout by hand: a 0–360° grid every 30°, a per-item axis of 3 items."""
    spec = from_data(_minimal(
        axis=[{"key": "cylinder", "zh": "缸", "en": "Cylinder"}],
        parameter=_minimal()["parameter"] + [
            {"key": "firing_angle", "group": "g", "unit": "deg", "zh": "f", "en": "f",
             "default": [0.0, 120.0, 240.0], "axis": "cylinder"},
            {"key": "law", "group": "g", "unit": "-", "zh": "l", "en": "l", "default": 1,
             "kind": "choice", "choices": ["cosine", "cycloidal"]}],
        sheet=_minimal()["sheet"] + [{"key": "c", "zh": "c", "en": "c", "kind": "items",
                                      "axis": "cylinder"}]))
    locator = Locator(spec, grid_rows={"angle": (5, 17)}, grid_numbers={"angle": (0.0, 30.0, 12)},
                      axis_sizes={"cylinder": 3})
    locator.places.update({"angle": Place("column", "S", 5, 0, grid="angle"),
                           "x": Place("column", "S", 5, 1, grid="angle"),
                           "firing_angle": Place("items", "C", 5, 1, count=3)})
    return spec, locator


@pytest.mark.parametrize("template,context,excel", [
    ("{x}", {"grid": "angle"}, "$B\x00"),
    ("{x}", {}, "q_x"),
    ("{x:prev}", {"grid": "angle"}, "$B\x01"),
    ("{x:head}", {}, "'S'!$B$6:$B$17"),
    ("{x|m}", {"grid": "angle"}, "($B\x00/1000)"),
    ("{angle|rad}", {"grid": "angle"}, "RADIANS($A\x00)"),
    ("{x:at(90)}", {"grid": "angle"}, "INDEX('S'!$B$6:$B$17,MOD(INT((90)/30+0.5),12)+1)"),
    ("{firing_angle}", {"item": 2, "axis": "cylinder"}, "'C'!$B$7"),
    ("{firing_angle}", {}, "p_firing_angle"),
    ("{firing_angle:item(3)}", {}, "'C'!$B$8"),
    ("{firing_angle:item({item}+1)}", {"item": 1, "axis": "cylinder"}, "'C'!$B$7"),
    ("{sum:cylinder({firing_angle})}", {}, "(('C'!$B$6)+('C'!$B$7)+('C'!$B$8))"),
    ("{sum:cylinder({index}*{item})}", {"item": 2, "axis": "cylinder"}, "((1*2)+(2*2)+(3*2))"),
    ("{law}", {}, 'MATCH(p_law,{"cosine","cycloidal"},0)'),
    ("{cycle}/4", {}, "360/4"),
])
def test_each_placeholder_compiles_to_the_documented_excel(template, context, excel):
    spec, locator = _locator()
    assert locator.compile(placeholders.parse(template), Context(sheet="S", **context)) == excel


# ---------------------------------------------------------------- inputs
def test_trace_is_wrapped_sorted_and_closed():
    angles, pressures = close_cycle("t", np.array([370.0, -360.0, 0.0, 10.0, 360.0] +
                                                  list(np.arange(20.0, 720.0, 20.0))),
                                    np.ones(40) * 0.2)
    assert angles[0] <= 0 and angles[-1] >= 720 and np.all(np.diff(angles) > 0)


def test_a_repeated_endpoint_that_differs_by_rounding_is_one_point():
    angles = np.arange(-360.0, 361.0, 10.0)
    pressures = 0.2 + 0.1 * np.cos(np.radians(angles))
    pressures[-1] *= 1 + 1e-9                     # 360° read back from another instrument
    got_a, got_p = close_cycle("t", angles, pressures)
    assert np.all(np.diff(got_a) > 0) and len(got_a) == 72 + 2


def test_grid_step_must_divide_the_cycle():
    spec = load("engine")
    assert len(evaluate.crank_angle_grid(spec, 0.5)) == 1441
    with pytest.raises(Exception, match="divide"):
        evaluate.crank_angle_grid(spec, 0.7)


@pytest.mark.parametrize("name", params.preset_names())
def test_every_preset_obeys_its_own_rules(name):
    spec, values, _ = params.load_preset(name)
    params.validate(spec, values)
    for p in spec.parameters:
        for value in (values[p.key] if p.axis else [values[p.key]]):
            assert not p.breaks_bounds(value), p.key


def test_the_language_is_documented_in_one_place():
    text = (Path(__file__).resolve().parent.parent / "docs" / "templates.md").read_text(
        encoding="utf-8")
    for part in placeholders.PARTS + placeholders.CALL_PARTS:
        assert f":{part}" in text, part
    for special in placeholders.SPECIAL + ("sum:", "|unit", "cycle"):
        assert special in text, special
    for construct in ("[[axis]]", "[[rule]]", "[[rulebook]]", "[[columnset]]", "[[sheet.use]]",
                      "[[sheet.charts]]", "equal_axes", "step_option", "guard", "array",
                      "discrete", "kind = \"choice\"", "[[constant]]", "[[input_table]]"):
        assert construct in text, construct


def test_a_quantity_takes_one_named_part_of_a_calc_result():
    """part = "y" of calc.cam.pitch_curve (a Point) is its y, exactly what the function
    gives; a part the result does not have is the template's SpecError, by name."""
    from crankbook.calc import cam
    column = {"formula": "{crank_radius}", "calc": "calc.cam.pitch_curve", "part": "y",
              "args": {"cam_angle": "angle", "displacement": "crank_radius",
                       "offset": "crank_radius", "base_radius": "crank_radius",
                       "rotation": "crank_radius"}}
    spec = from_data(_with_column(**column))
    out = evaluate.evaluate(spec, {"crank_radius": 50.0})
    angle = np.radians(np.arange(0, 361, 30))
    assert np.allclose(out["y"] / 1000, cam.pitch_curve(angle, 0.05, 0.05, 0.05, 0.05).y,
                       rtol=1e-15, atol=0)
    bad = from_data(_with_column(**{**column, "part": "z"}))
    with pytest.raises(SpecError, match="y: calc 'calc.cam.pitch_curve' has no part 'z'"):
        evaluate.evaluate(bad, {"crank_radius": 50.0})


def test_a_templates_defaults_override_its_librarys():
    """[defaults] gives the template's own default to a library's parameter; a key
    nothing defines is an authoring mistake."""
    data = _minimal(include=["pin_strength"], defaults={"crankpin_diameter": 70.0})
    spec = from_data(data)
    assert spec.parameter["crankpin_diameter"].default == 70.0
    assert load("engine").parameter["crankpin_diameter"].default == 48.0
    with pytest.raises(SpecError, match="no library defines"):
        from_data(_minimal(defaults={"no_such_input": 1.0}), file="mine.toml")


def test_a_target_names_a_key_of_the_workbook():
    """``target`` colours a factor against a key's live value: a key the workbook does
    not have is refused when the template loads; a key it has, or a number, loads."""
    with pytest.raises(SpecError, match="y: target 'nope' is not a key of this workbook"):
        from_data(_with_column(formula="{x}", target="nope"))
    from_data(_with_column(formula="{x}", target="crank_radius"))
    from_data(_with_column(formula="{x}", target=2.0))


def test_item_names_come_in_both_languages():
    data = _minimal()
    data["axis"] = [{"key": "check", "zh": "校核", "en": "Checks", "size_calc":
                     "calc.connecting_rod.check_count", "item_names_zh": ["一", "二"],
                     "item_names_en": ["one"]}]
    with pytest.raises(SpecError, match="check: item_names_zh and item_names_en"):
        from_data(data)


@pytest.mark.parametrize("zh,en", [
    (["前端", "曲拐 {each}", "{each}"], ["Front", "Throw {each}", "{each}"]),   # two runs
    (["前端", "曲拐 {each}", "飞轮"], ["Front {each}", "Throw", "Flywheel"]),    # misplaced
    (["前端", "曲拐", "飞轮"], ["Front", "Throw {each}", "Flywheel"]),           # one language
])
def test_a_repeated_item_name_is_one_entry_in_both_languages(zh, en):
    data = _minimal()
    data["axis"] = [{"key": "station", "zh": "质量", "en": "Stations", "size_calc":
                     "calc.torsional.station_count", "size_args": {"throw": "throw"},
                     "item_names_zh": zh, "item_names_en": en}]
    with pytest.raises(SpecError, match=r"station: item names hold \{each\} in one entry"):
        from_data(data)


def test_a_repeated_item_name_fills_the_items_the_fixed_names_leave():
    """"Throw {each}" stands for every item between the front and the flywheel, counted
    from 1 in it, for any size; a size with no room for the fixed names names nothing."""
    from crankbook.spec.model import Axis
    axis = Axis(key="station", zh="质量", en="Stations", label_zh="质量", label_en="Station",
                item_names_zh=("前端", "曲拐 {each}", "飞轮"),
                item_names_en=("Front", "Throw {each}", "Flywheel"))
    for throws in (1, 2, 5):
        names = axis.names("en", throws + 2)
        assert names == ("Front", *(f"Throw {k}" for k in range(1, throws + 1)), "Flywheel")
        assert [axis.label("en", i + 1, size=throws + 2) for i in range(throws + 2)] == \
            list(names)
    assert axis.names("zh", 3) == ("前端", "曲拐 1", "飞轮")
    assert axis.names("en", 2) == ("Front", "Flywheel")         # no throw: the run is empty
    assert axis.names("en", 1) == ()
    assert axis.label("en", 2) == "Station 2"                   # no size: the axis's label
    assert axis.live_keys == ()                                 # {each} holds no result


@pytest.mark.parametrize("held,words", [
    ("nope", "holds {nope}: it must be a result of one whole number"),
    ("x", "holds {x}: it must be a result of one whole number"),          # a series
    ("crank_radius", "holds {crank_radius}: it must be a result"),        # an input
])
def test_an_item_name_holds_only_a_whole_number_result(held, words):
    """A name that holds a result (the main bearing's number) is a text formula of a
    discrete scalar: anything else — unknown, a column, an input — is refused."""
    data = _minimal()
    data["axis"] = [{"key": "check", "zh": "校核", "en": "Checks", "size_calc":
                     "calc.connecting_rod.check_count", "item_names_zh": [f"第 {{{held}}} 道"],
                     "item_names_en": [f"Bearing {{{held}}}"]}]
    with pytest.raises(SpecError, match=f"check: an item's name {re.escape(words)}"):
        from_data(data)


def test_a_long_label_is_cut_into_excels_string_constants():
    """A name that holds a result is a text formula; Excel refuses a string constant
    over 255 characters, so a long label is written as pieces joined by &."""
    from crankbook.writer import live_text
    text = 'Bearing "A" ' + "x" * 600
    formula = live_text.quoted(text)
    constants = re.findall(r'"((?:[^"]|"")*)"', formula)
    assert all(len(c.replace('""', '"')) <= 255 for c in constants)
    assert "".join(c.replace('""', '"') for c in constants) == text
    assert live_text.quoted("") == '""'
