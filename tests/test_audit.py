"""The audit: claims files, their live workbook against Python, the returned-workbook
check (tampered cells reported with their address), and bad input."""
import json
import re
import shutil
import zipfile

import numpy as np
import openpyxl
import pytest

from crankbook.calc import mechanism
from tests.conftest import run_cli
from tests.test_cli import _assert_clean_refusal
from crankbook import claims, recalc

DOCUMENTS = ["thesis", "course-report", "compressor", "offset-piston", "balancing-ring"]


def test_every_document_has_claims_file():
    assert sorted(DOCUMENTS) == claims.document_names()


@pytest.mark.parametrize("name", DOCUMENTS)
def test_claims_load_and_evaluate(name):
    document = claims.load(name)
    assert len(document.claims) >= 5
    for finding in document.findings():
        assert finding["status"] in ("ok", "mismatch", "inconsistent", "unverifiable")
        assert finding["note"], finding["claim"]
        if finding["status"] == "unverifiable":
            assert finding["recomputed"] is None
        else:
            assert np.isfinite(finding["recomputed"])


def test_equivalent_ring_mass_is_the_mean_kinetic_energy():
    # seed 004 eq. 4: M = m2 + m1/2 + m1·λ²/8, against a numerical average
    for lam in (1 / 6, 0.25, 1 / 3):
        m = mechanism.equivalent_ring_mass(1.3, 0.7, lam)
        assert m == pytest.approx(0.7 + 1.3 / 2 + 1.3 * lam ** 2 / 8, rel=1e-12)


def test_seed_002_safety_factor():
    # n = σ−1 / (kσ/(β·εσ)·σa + ψσ·σm), by hand: 495 / (1.37778·178.45 + 88.3245)
    claim = next(c for c in claims.load("compressor").claims if c.key == "safety_factor")
    assert claim.recompute() == pytest.approx(495 / (1.55 / 1.125 * 178.45 + 0.33 * 267.65))
    assert claim.status(claim.recompute()) == "ok"


def test_known_verdicts():
    status = {(name, c.key): c.status(c.recompute())
              for name in DOCUMENTS for c in claims.load(name).claims}
    assert status[("offset-piston", "opt_e")] == "ok"
    assert status[("offset-piston", "reduction_abstract")] == "mismatch"
    assert status[("offset-piston", "reduction_conclusion")] == "inconsistent"
    assert status[("thesis", "gas_force_area")] == "inconsistent"
    assert status[("thesis", "pin_length")] == "mismatch"
    assert status[("thesis", "combined_stress")] == "inconsistent"
    assert status[("thesis", "reciprocating_mass")] == "unverifiable"
    assert status[("compressor", "crank_radius")] == "inconsistent"


def test_audit_all_writes_workbook_report_and_json(tmp_path):
    out = tmp_path / "audit.xlsx"
    done = run_cli("audit", "all", "-o", out, "--json", tmp_path / "f.json")
    assert done.returncode == 0, done.stderr
    data = json.loads((tmp_path / "f.json").read_text(encoding="utf-8"))
    fields = {"document", "section", "claim", "reported", "unit", "recomputed", "status", "note"}
    assert data["findings"] and all(set(f) == fields for f in data["findings"])
    assert {f["document"] for f in data["findings"]} == set(DOCUMENTS)
    report = (tmp_path / "audit.md").read_text(encoding="utf-8")
    assert "| thesis |" in report and "inconsistent" in report
    assert out.is_file()


@pytest.mark.libreoffice
def test_audit_workbook_formulas_agree_with_python(soffice, tmp_path):
    out = tmp_path / "audit.xlsx"
    assert run_cli("audit", "all", "-o", out).returncode == 0
    converted = recalc.convert([out], tmp_path / "lo")[0]
    book = openpyxl.load_workbook(converted, data_only=True)
    for name in DOCUMENTS:
        ws = book[name]
        header = [c.value for c in ws[4]]
        rows = {r[0]: dict(zip(header, r)) for r in ws.iter_rows(min_row=5, values_only=True)
                if r[0]}
        for claim in claims.load(name).claims:
            row = rows[claim.key]
            recomputed = claim.recompute()
            assert row["status"] == claim.status(recomputed), (name, claim.key)
            if recomputed is not None:
                assert row["recomputed"] == pytest.approx(recomputed, rel=1e-9, abs=1e-12), \
                    (name, claim.key)
    counts = {r[0]: r[1:5] for r in book["Summary"].iter_rows(min_row=4, values_only=True)
              if r[0]}
    for name in DOCUMENTS:
        statuses = [c.status(c.recompute()) for c in claims.load(name).claims]
        assert list(counts[name]) == [statuses.count(s) for s in
                                      ("ok", "mismatch", "inconsistent", "unverifiable")]


def _set_cached_value(path, sheet_index, cell, value, drop_formula=False):
    """Rewrite one cell's stored value inside the xlsx zip (as a user's edit would)."""
    member = f"xl/worksheets/sheet{sheet_index}.xml"
    with zipfile.ZipFile(path) as source:
        items = {n: source.read(n) for n in source.namelist()}
    xml = items[member].decode()
    pattern = re.compile(rf'(<c r="{cell}"[^>]*>)(<f>[^<]*</f>)?<v>[^<]*</v>')
    assert pattern.search(xml), cell
    xml = pattern.sub(lambda m: m.group(1) + ("" if drop_formula else (m.group(2) or ""))
                      + f"<v>{value}</v>", xml, count=1)
    items[member] = xml.encode()
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as target:
        for name, data in items.items():
            target.writestr(name, data)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("tamper")
    path = tmp / "engine.xlsx"
    assert run_cli("build", "--step", "10", "--lang", "en", "-o", path).returncode == 0
    return path


def test_untouched_workbook_passes(built):
    done = run_cli("audit", built)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "every q_ cell agrees" in done.stdout


def test_tampered_cell_is_reported_with_its_address(built, tmp_path):
    book = openpyxl.load_workbook(built)
    sheet_index = book.sheetnames.index("Torque") + 1
    tampered = tmp_path / "tampered.xlsx"
    shutil.copy(built, tampered)
    _set_cached_value(tampered, sheet_index, "B12", "999.5")           # a pasted-over result
    _set_cached_value(tampered, sheet_index, "C20", "-1", drop_formula=True)  # typed over
    done = run_cli("audit", tampered)
    assert done.returncode == 1
    assert "'Torque'!B12" in done.stdout and "value differs" in done.stdout
    assert "'Torque'!C20" in done.stdout and "formula replaced by a constant" in done.stdout
    assert done.stdout.count("\n") <= 6, "only the tampered cells are reported"


@pytest.mark.parametrize("content,expected", [
    (b"not a workbook", "not an .xlsx file"),
    ({"hello.txt": b"a zip, but no workbook"}, "not an .xlsx workbook"),
])
def test_bad_files_are_refused(tmp_path, content, expected):
    path = tmp_path / "returned.xlsx"
    if isinstance(content, dict):
        with zipfile.ZipFile(path, "w") as archive:
            for name, data in content.items():
                archive.writestr(name, data)
    else:
        path.write_bytes(content)
    done = run_cli("audit", path)
    assert done.returncode == 2 and expected in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr


def test_workbook_without_names_is_refused(tmp_path):
    path = tmp_path / "plain.xlsx"
    openpyxl.Workbook().save(path)
    done = run_cli("audit", path)
    assert done.returncode == 2 and "no p_ and q_ names" in done.stderr


def test_unknown_document_is_refused(tmp_path):
    out = tmp_path / "a.xlsx"
    done = run_cli("audit", "nosuchdoc", "-o", out)
    _assert_clean_refusal(done, "unknown document 'nosuchdoc'", out)
