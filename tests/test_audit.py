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
        assert finding["status"] in claims.VERDICTS
        assert finding["note"] or finding["status"] == "unverifiable", finding["claim"]
        assert finding["line"] >= 1
        if finding["status"] == "unverifiable":
            assert finding["recomputed"] is None or finding["reported"] is None
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
    # the same situation (arithmetic of two printed peaks) gets the same verdict
    assert status[("offset-piston", "accel_reduction")] == \
        status[("offset-piston", "side_reduction")] == "ok"
    assert status[("thesis", "gas_force_diameter")] == "inconsistent"
    assert status[("thesis", "pin_length")] == "outside-rule"
    assert status[("thesis", "web_width")] == "outside-rule"
    assert status[("thesis", "combined_stress")] == "inconsistent"
    assert status[("thesis", "tangential_min")] == "model-disagrees"
    assert status[("thesis", "bending_stress")] == "mismatch"
    assert status[("thesis", "reciprocating_mass")] == "unverifiable"
    assert status[("compressor", "crank_radius")] == "inconsistent"
    assert status[("compressor", "shaft_power_from_the_workbook")] == "model-disagrees"
    assert status[("course-report", "listing_lengths")] == "inconsistent"
    assert status[("course-report", "r07_da1")] == "mismatch"        # digits transposed


def test_verdicts_mean_one_thing():
    """Claims with the same kind of recomputation and the same outcome share a
    verdict, and each verdict carries what it rests on."""
    seen = {}
    for name in DOCUMENTS:
        for claim, finding in zip(claims.load(name).claims, claims.load(name).findings()):
            recomputed, compared = finding["recomputed"], claim.compared()
            outcome = "none" if recomputed is None or compared is None else \
                claim.within(recomputed)
            seen.setdefault((claim.kind, outcome), set()).add(finding["status"])
            if finding["status"] == "inconsistent":
                assert claim.other and claim.other_line, claim.key
            if finding["status"] == "model-disagrees":
                assert claim.model, claim.key
            if finding["status"] == "unverifiable":
                assert claim.missing, claim.key
            assert (finding["margin_percent"] is not None) == \
                (finding["status"] == "outside-rule"), claim.key
    assert all(len(verdicts) == 1 for verdicts in seen.values()), seen
    assert seen[("value", False)] == {"mismatch"} and seen[("rule", False)] == {"outside-rule"}


def test_course_report_table_against_the_kinematics():
    """The 2.3 table's entries: crankbook's exact crank-slider kinematics (calc/) with
    the report's L1 = 135, L2 = 170 mm and ω1 = 68.068 rad/s give the recomputation;
    the derived patterns (λ = 0.7647, ω2 from 34 rad/s) reproduce the printed columns."""
    from crankbook.calc import kinematics
    found = {c.key: c for c in claims.load("course-report").claims}
    r, l, w = 0.135, 0.170, 68.068
    for phi in range(0, 361, 10):
        psi = np.radians(phi)
        s = (r + l - kinematics.piston_displacement_exact(psi, r, l, 0.0)) * 1000
        v = -kinematics.piston_velocity_exact(psi, r, l, 0.0, w) * 1000
        a = -kinematics.piston_acceleration_exact(psi, r, l, 0.0, w) * 1000
        for key, value in (("s", s), ("v", v), ("a", a)):
            claim = found[f"motion_{key}_{phi}"]
            assert claim.recompute() == pytest.approx(value, rel=1e-9, abs=1e-6), (key, phi)
        theta2 = found[f"motion_theta2_{phi}"]
        assert abs(theta2.derived_value() - theta2.reported) <= 0.01 + 1e-9   # a unit of its last digit
    for key in ("v", "w2", "a"):
        column = [c for k, c in found.items() if k.startswith(f"motion_{key}_")]
        peak = max(abs(c.reported) for c in column)
        assert max(abs(c.derived_value() - c.reported) for c in column) < 0.005 * peak
        assert max(abs(c.recompute() - c.reported) for c in column) > 0.02 * peak
    assert found["motion_a_0"].recompute() == pytest.approx(-1122201, rel=1e-5)
    assert found["motion_w2_0"].recompute() == pytest.approx(-68.068 * 135 / 170)


def test_audit_all_writes_workbook_report_and_json(tmp_path):
    out = tmp_path / "audit.xlsx"
    done = run_cli("audit", "all", "-o", out, "--json", tmp_path / "f.json")
    assert done.returncode == 0, done.stderr
    data = json.loads((tmp_path / "f.json").read_text(encoding="utf-8"))
    from crankbook.audit_book import FINDING_FIELDS
    assert data["findings"] and all(set(f) == set(FINDING_FIELDS) for f in data["findings"])
    assert {f["document"] for f in data["findings"]} == set(DOCUMENTS)
    assert all(isinstance(f["line"], int) for f in data["findings"])
    assert set(data["verdicts"]) == set(claims.VERDICTS)
    assert data["coverage"]["thesis"]["omitted"]
    report = (tmp_path / "audit.md").read_text(encoding="utf-8")
    assert "| thesis |" in report and "model-disagrees" in report
    assert "**outside-rule** (-9.1 %)" in report               # L2 = 20 mm against 22–39.6
    assert out.is_file()


@pytest.mark.libreoffice
def test_audit_workbook_formulas_agree_with_python(soffice, tmp_path):
    from crankbook.audit_book import HEADER_ROW, STATUSES
    out = tmp_path / "audit.xlsx"
    assert run_cli("audit", "all", "-o", out).returncode == 0
    converted = recalc.convert([out], tmp_path / "lo")[0]
    book = openpyxl.load_workbook(converted, data_only=True)
    for name in DOCUMENTS:
        ws = book[name]
        header = [c.value for c in ws[HEADER_ROW + 1]]
        rows = {r[0]: dict(zip(header, r))
                for r in ws.iter_rows(min_row=HEADER_ROW + 2, values_only=True) if r[0]}
        for claim in claims.load(name).claims:
            row = rows[claim.key]
            recomputed = claim.recompute()
            assert row["verdict"] == claim.status(recomputed), (name, claim.key)
            assert row["line"] == claim.line
            if recomputed is not None:
                assert row["recomputed"] == pytest.approx(recomputed, rel=1e-9, abs=1e-12), \
                    (name, claim.key)
            margin = claim.margin_percent(recomputed)
            if margin is not None:
                assert row["margin %"] == pytest.approx(margin, rel=1e-9)
    counts = {r[0]: r[1:1 + len(STATUSES)]
              for r in book["Summary"].iter_rows(min_row=HEADER_ROW + 2,
                                                 max_row=HEADER_ROW + 1 + len(DOCUMENTS),
                                                 values_only=True)}
    for name in DOCUMENTS:
        statuses = [c.status(c.recompute()) for c in claims.load(name).claims]
        assert list(counts[name]) == [statuses.count(s) for s in STATUSES]


def _set_cached_value(path, sheet_index, cell, value, drop_formula=False):
    """Rewrite one cell's stored value inside the xlsx zip (as a user's edit would)."""
    member = f"xl/worksheets/sheet{sheet_index}.xml"
    with zipfile.ZipFile(path) as source:
        items = {n: source.read(n) for n in source.namelist()}
    xml = items[member].decode()
    # a formula is <f>…</f>, or <f t="shared" …/> in a filled-down column
    pattern = re.compile(rf'(<c r="{cell}"[^>]*>)(<f[^>]*/>|<f[^>]*>[^<]*</f>)?<v>[^<]*</v>')
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


# ---------------------------------------------------------------- anchoring (issue 15)
def _seeds():
    """The source documents: $CRANKBOOK_SEEDS, else ../shared/seeds beside the repo."""
    import os
    from pathlib import Path
    folder = Path(os.environ.get("CRANKBOOK_SEEDS") or
                  Path(__file__).resolve().parents[2] / "shared" / "seeds")
    if not folder.is_dir():
        pytest.fail(f"the seed documents are not at {folder}: set CRANKBOOK_SEEDS")
    return folder


@pytest.mark.parametrize("name", DOCUMENTS)
def test_every_reported_number_is_printed_at_its_line(name):
    problems = claims.anchor_problems(claims.load(name), _seeds())
    assert not problems, problems


def test_the_anchor_check_can_fail():
    claim = claims.Claim(key="k", section="s", line=2, claim="c", unit="mm", reported=44.5)
    assert claims.anchor_problem(claim, ["L1=44.5mm", "L2=21.5mm"]) is not None
    assert claims.anchor_problem(claim, ["x", "L1=(23+20)/2+23=44.5mm"]) is None
    fraction = claims.Claim(key="k", section="s", line=1, claim="c", unit="-",
                            reported=0.25, printed="1/3")
    assert "not the reported" in claims.anchor_problem(fraction, ["λ=1/3"])
    assert claims.anchor_problem(
        claims.Claim(key="k", section="s", line=1, claim="c", unit="N", reported=26391.0),
        ["Ptmax=26 391N"]) is None                      # thousands separators


@pytest.mark.parametrize("content,words", [(None, "is not there"),
                                           (b"\xff\xfe\xff", "cannot be read as UTF-8")])
def test_bad_sources_folder_is_one_line_and_writes_nothing(tmp_path, content, words):
    sources = tmp_path / "seeds"
    sources.mkdir()
    if content is not None:
        (sources / claims.load("thesis").file).write_bytes(content)
    out = tmp_path / "audit.xlsx"
    done = run_cli("audit", "thesis", "-o", out, "--sources", sources)
    _assert_clean_refusal(done, words, out)
    assert not out.with_suffix(".md").exists()


def test_sources_with_a_misplaced_number_exit_1(tmp_path):
    sources = tmp_path / "seeds"
    sources.mkdir()
    lines = (_seeds() / claims.load("thesis").file).read_text(encoding="utf-8").splitlines()
    lines[368] = "r = 100/2 = 49 mm"                      # crank_radius's line, altered
    (sources / claims.load("thesis").file).write_text("\n".join(lines), encoding="utf-8")
    done = run_cli("audit", "thesis", "-o", tmp_path / "a.xlsx", "--sources", sources)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "thesis: crank_radius: 50 does not occur at line 369" in done.stdout
