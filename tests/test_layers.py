"""The packages import one way (issue 29): a newcomer can trust that the template
language knows nothing of the writer, the writer nothing of reading, and so on up
to the command line.  Every import is parsed, those inside functions too."""
import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# lowest first: a module imports only from its own part or from a lower layer
LAYERS = [
    {"errors", "support", "calc"},    # no part imports another here but support → errors
    {"spec"},                         # the template language
    {"writer"},                       # writes .xlsx (and the torsion CSVs)
    {"reading"},                      # reads, recalculates and compares workbooks
    {"results"},                      # Results: computed (compute) or read back (read)
    {"audit", "assignment"},          # the auditor's and the teacher's workflows
    {"api"},                          # the public API
    {"cli", "__main__"},              # the command line
]
LAYER = {part: n for n, parts in enumerate(LAYERS) for part in parts}
ALLOWED_SIDEWAYS = {("support", "errors"), ("__main__", "cli")}


def _modules():
    """(part, file) of every module: workbook/ is crankbook, calc/ is crankbook.calc."""
    for path in sorted((ROOT / "workbook").rglob("*.py")):
        relative = path.relative_to(ROOT / "workbook")
        if relative.parts == ("__init__.py",):
            continue                               # the package root re-exports the API
        yield relative.parts[0].removesuffix(".py"), path
    for path in sorted((ROOT / "calc").rglob("*.py")):
        yield "calc", path


def _part_of(dotted):
    """crankbook.spec.units -> spec; crankbook (the root) -> None."""
    names = dotted.split(".")
    if names[0] != "crankbook" or len(names) == 1:
        return None
    return names[1]


def _imports(path):
    """Every crankbook module a file imports (``from crankbook import x`` is module x
    when x is one, else the root)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "crankbook":
                for alias in node.names:
                    module = (ROOT / "workbook" / alias.name)
                    is_module = module.with_suffix(".py").exists() or module.is_dir()
                    yield (f"crankbook.{alias.name}" if is_module else "crankbook"), node.lineno
            else:
                yield node.module, node.lineno


def test_every_import_goes_down_the_layers():
    wrong = []
    for part, path in _modules():
        assert part in LAYER, f"{path}: a module outside every layer ({part})"
        for module, line in _imports(path):
            target = _part_of(module)
            if target is None or target == part:
                continue
            assert target in LAYER, f"{path}:{line}: imports {module}, in no layer"
            same = LAYER[target] == LAYER[part]
            if LAYER[target] > LAYER[part] or same and (part, target) not in ALLOWED_SIDEWAYS:
                wrong.append(f"{path.relative_to(ROOT)}:{line} ({part}) imports {module}")
    assert not wrong, "\n".join(wrong)


def test_calc_is_pure_physics():
    """calc/ imports numpy and its own modules only: no I/O, no spreadsheet."""
    for path in sorted((ROOT / "calc").rglob("*.py")):
        for module, line in _imports(path):
            top = module.split(".")[0]
            assert top in ("numpy", "math", "typing", "dataclasses", "functools") or \
                module.startswith("crankbook.calc"), f"{path.name}:{line} imports {module}"


def test_the_layers_catch_an_upward_import(tmp_path, monkeypatch):
    """The check can fail: a spec module that imported the writer would be named."""
    fake = tmp_path / "workbook" / "spec"
    fake.mkdir(parents=True)
    (fake / "bad.py").write_text("from crankbook.writer.build import write_workbook\n")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    (tmp_path / "calc").mkdir()
    try:
        test_every_import_goes_down_the_layers()
    except AssertionError as error:
        assert "spec/bad.py:1 (spec) imports crankbook.writer.build" in str(error)
    else:
        raise AssertionError("an upward import passed")
