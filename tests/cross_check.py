"""The workbooks every spreadsheet-engine cross-check recalculates, built once.

Each entry is built through the command line (``args``) or made from another by
typing into its input cells (``edit_of``, ``edits``, ``tables``), as a user would.
The expected values are numpy's, evaluated on the inputs stored in each file —
never on what the writer computed.  LibreOffice recalculates all files in one run,
Gnumeric one by one.
"""
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from crankbook.reading import recalc
from crankbook.reading.verification import expected_values
from crankbook.reading.workbook_reader import load_named
from tests.conftest import edit_cells, named, named_computed, run_cli

ENGINES = ("libreoffice", "gnumeric")
BATCH_TIMEOUT = 1800             # s: the whole batch's hang guard
# the workbooks whose files, as each engine saves them, tests open (an engineer's
# LibreOffice save read by the users' commands; the audit of an engine's save)
SAVED = {"libreoffice": ("thesis_step3", "course", "optimization", "inline6_step3"),
         "gnumeric": ("thesis_step3", "course", "optimization")}
PASTED_TRACE = np.arange(-5.0, 726.0, 5.0)
WORKBOOKS = {
    # the thesis engine (issue 3) ------------------------------------------------
    "thesis": {"args": []},
    # typing into a coarser grid: the same formulas, a third of the engines' time
    "thesis_step3": {"args": ["--step", "3"]},
    "thesis_offset_en": {"args": ["--set", "offset=12", "--set", "exact_kinematics=1",
                                  "--set", "rod_length=165", "--lang",
                                  "en", "--step", "2"]},
    "thesis_exact": {"args": ["--set", "exact_kinematics=1", "--set", "speed=3200", "--step",
                              "2"]},
    "thesis_measured": {"args": ["--pressure", "{trace}", "--step", "0.5"]},
    # … and a viscous damper at the front (issue 42): the response with and without it
    "thesis_edit_offset": {"edit_of": "thesis_step3",
                           "edits": {"offset": -9.0, "rod_length": 172.0, "bore": 92.0,
                                     "exact_kinematics": 1.0, "damper_kind": 1.0,
                                     "damper_inertia": 0.003, "damper_damping": 2.5,
                                     # an SAE grade's oil at 110 °C (issue 45)
                                     "oil_grade": "SAE40", "oil_temperature": 383.15}},
    # … and a textbook's three-rotor system typed over the computed one (issue 28)
    "thesis_edit_speed": {"edit_of": "thesis_step3",
                          "edits": {"speed": 2300.0, "crank_radius": 45.0, "piston_mass": 0.41,
                                    # a typed I-section, a cut thread, a typed joint
                                    # constant and over-speed, a fine M10 of class 8.8
                                    # (issue 44)
                                    "rod_section_standard": 0.0, "rod_flange_width": 20.0,
                                    "rod_section_height": 26.0, "rod_web_thickness": 4.0,
                                    "bolt_thread_rolled": 0.0, "overspeed": 2900.0,
                                    "bolt_joint_constant_typed": 0.25, "bolt_size": "M10x1",
                                    "bolt_property_class": 8.8, "bolt_span_typed": 70.0,
                                    # the second main bearing, a wider gap, thinner
                                    # oil and a groove (issue 45)
                                    "check_bearing": 2.0, "bearing_clearance": 45.0,
                                    "oil_viscosity": 6.0, "oil_groove_width": 3.0,
                                    "station_inertia_typed": [0.3, 1.2, 0.7],
                                    "section_stiffness_typed": [2.0e5, 3.5e5],
                                    "holzer_step": 1.0,
                                    # M68's own σ_B typed over the crankshaft's
                                    "shaft_tensile_strength": 700.0}},
    # … and a Holzer grid too fine to reach the first mode: blank, and the status says why
    # … and a bush that turns loose when warm: its fit check blank, the rod failed
    # … and a 200 µm gap with 2 mPa·s oil whose big-end film breaks down: rows held
    # at the eccentricity limit, flagged
    "thesis_edit_exact": {"edit_of": "thesis_step3", "edits": {"exact_kinematics": 1.0, "speed": 6100.0,
                                                                "bearing_clearance": 200.0,
                                                                "oil_viscosity": 2.0,
                                                                "holzer_step": 0.001,
                                                                "bush_interference": 0.0,
                                                                "bush_expansion": 6.0,
                                                                # … and an allowable film typed in mm
                                                                "min_film_allowable": 0.001}},
    "thesis_edit_trace": {"edit_of": "thesis_step3", "edits": {"pressure_source": 1.0},
                          "tables": {"trace_crank_angle": PASTED_TRACE,
                                     "trace_pressure": 0.12 + 3.0 * np.exp(
                                         -((PASTED_TRACE - 372) / 25) ** 2)}},
    "thesis_invalid": {"edit_of": "thesis_step3", "edits": {"rod_length": 40.0}, "valid": False},
    # the course design (issue 4) ------------------------------------------------
    "course": {"args": ["--preset", "course-design"]},
    "course_group1_en": {"args": ["--preset", "course-design", "--group", "1", "--lang", "en"]},
    "course_group6_step2": {"args": ["--preset", "course-design", "--group", "6", "--step", "2",
                                     "--cam-step", "3"]},
    "course_group12": {"args": ["--preset", "course-design", "--group", "12"]},
    # a measured trace whose points fall exactly on grid and position angles (30°, …)
    "course_measured": {"args": ["--preset", "course-design", "--pressure", "{course_trace}",
                                 "--step", "3"]},
    "course_edited": {"edit_of": "course", "edits": {"time_ratio": 1.12, "offset": 35.0,
                                                     "speed": 900.0, "crank_cg_ratio": 0.0}},
    "optimization": {"args": ["--preset", "offset-optimization"]},
    # the valve train (issue 13), typed into the cells: laws, a mirrored cam, gears
    "course_edit_valve_train": {"edit_of": "course",
                                "edits": {"intake_rise_law": "cycloidal",
                                          "intake_return_law": "3-4-5",
                                          "exhaust_rise_law": "constant_acceleration",
                                          "exhaust_return_law": "constant_velocity",
                                          "exhaust_rotation": -1.0, "intake_offset": -4.0,
                                          "gear_teeth": [21.0, 15.0, 42.0],
                                          "gear_shift": [0.0, 0.11765, 0.0],
                                          "gear_module": 4.0, "intake_opens": -12.0}},
    # multi-cylinder layouts (issue 11) ------------------------------------------
    # … with a tuned rubber damper at the front (issue 42)
    "inline4": {"args": ["--preset", "inline-4", "--step", "4", "--set", "damper_kind=2",
                         "--set", "damper_inertia=0.008", "--set", "damper_stiffness=4e4",
                         "--set", "damper_damping=6"]},
    # … with a Holzer grid that ends at 600 Hz: its last 200 rows are blank
    # (three operating points where the speed range is not what is checked: with the
    # pressure from the charge each point has its own pressure columns)
    "inline6_step3": {"args": ["--preset", "inline-6", "--step", "3", "--set",
                               "holzer_max_frequency=600", "--set", "operating_speed=1500,4000,6500"]},
    # … and M18 bolts of class 8.8 (its strengths above M16) with a typed grip
    "v8_counterweights": {"args": ["--preset", "v8-crossplane", "--set", "counterweights=1",
                                   "--set", "bolt_size=M18x1.5", "--set", "bolt_property_class=8.8",
                                   "--set", "bolt_grip_typed=30",
                                   "--set", "balance_fraction=0.5", "--step", "3", "--set", "operating_speed=1500,4000,6500"]},
    "vtwin_series_step2_en": {"args": ["--preset", "v-twin-90", "--set", "exact_kinematics=0",
                                       "--step", "2", "--lang", "en", "--set", "operating_speed=1500,4000,6500"]},
    "boxer4": {"args": ["--preset", "boxer-4", "--set", "counterweights=1", "--step", "4",
                        "--set", "operating_speed=1500,4000,6500"]},
    "inline4_edit_layout": {"edit_of": "inline4",
                            "edits": {"firing_angle": [360.0, 540.0, 180.0, 0.0],
                                      "bank_angle": [10.0, 10.0, 10.0, 10.0],
                                      "axial_position": [0.0, 90.0, 180.0, 270.0],
                                      "counterweights": 1.0, "speed": 3100.0}},
    # the compressor (issue 14) ---------------------------------------------------
    "compressor": {"args": ["--preset", "compressor"]},
    "compressor_one_stage_en": {"args": ["--preset", "compressor", "--lang", "en", "--step", "2",
                                         "--set", "stage_bore=60", "--set",
                                         "stage_suction_pressure=0.1", "--set",
                                         "stage_discharge_pressure=0.8", "--set",
                                         "stage_expansion_exponent=1.3", "--set",
                                         "stage_compression_exponent=1.35", "--set",
                                         "stage_clearance_length=1", "--set", "stage_column=1"]},
    "compressor_edited": {"edit_of": "compressor",
                          "edits": {"speed": 1200.0, "ambient_pressure": 0.1,
                                    "stage_suction_pressure": [0.1, 0.5, 3.0],
                                    "stage_discharge_pressure": [0.5, 3.0, 18.0],
                                    "column_phase": [0.0, 90.0], "friction_coefficient": 0.6,
                                    "check_throw": 1.0, "crankpin_bore": 20.0,
                                    "strength_theory": 4.0}},
    # the crankshaft (issue 12) -------------------------------------------------
    "thesis_edit_crankshaft": {"edit_of": "thesis_step3",
                               "edits": {"strength_theory": 4.0, "crankpin_bore": 16.0,
                                         "check_angle": 400.0, "fatigue_stress_source": 1.0,
                                         "alternative_stroke": 104.0, "counterweights": 1.0,
                                         "exhaust_valve_opening": 480.0}},
    "inline4_check_throw3": {"args": ["--preset", "inline-4", "--set", "check_throw=3",
                                      "--set", "check_bearing=3",
                                      "--set", "counterweights=1", "--step", "4",
                                      "--set", "operating_speed=1500,4000,6500"]},
    "inline4_invalid_throw": {"edit_of": "inline4", "edits": {"throw": [1.0, 1.0, 3.0, 4.0]},
                              "valid": False},
    # the speed range (issue 21): a measured trace per speed, on one and eight cylinders
    "thesis_speed_traces": {"args": ["--pressure", "{bench}", "--step", "2"]},
    "v8_speed_traces": {"args": ["--preset", "v8-crossplane", "--pressure", "{bench}",
                                 "--step", "6", "--set", "check_throw=2"]},
    # … the design speed typed over with another of the file's speeds: its trace is not
    # on the Pressure sheet, so every result goes blank and the status says why
    # the charge (issue 41): the thesis engine's heat from its charge, the combustion
    # angles and η_v from the table, friction typed per point, in English
    "thesis_charge_en": {"args": ["--set", "heat_release_source=charge", "--set",
                                  "combustion_timing=table", "--set", "friction_source=typed",
                                  "--set", "operating_fmep_typed=0.1,0.12,0.14,0.16,0.18,0.2,"
                                  "0.22,0.24,0.26,0.28,0.3,0.32", "--set",
                                  "stroke_study_pressure=model", "--step", "3", "--lang", "en"]},
    # … a charge table typed into the cells out of order: the status says so
    "thesis_charge_unordered": {"edit_of": "thesis_charge_en",
                                "edits": {"charge_speed": [1000.0, 3000.0, 2000.0, 4000.0,
                                                           5000.0, 6000.0, 7000.0]},
                                "valid": False},
    # … and a workbook laid out with one pressure for every speed switched to the charge
    # in its cells: its points cannot each get a pressure until it is rebuilt, and say so
    "thesis_switched_to_charge": {"edit_of": "thesis_step3",
                                  "edits": {"heat_release_source": "charge"}, "valid": False},
    "thesis_traces_speed_edited": {"edit_of": "thesis_speed_traces", "edits": {"speed": 3500.0},
                                   "valid": False},
}


@dataclass
class Checked:
    """One workbook: its spec, numpy's values and floors for its own stored inputs,
    the values stored in the file, and each engine's recalculated names."""
    path: object
    spec: object
    expected: dict | None
    floors: dict | None
    cached: dict
    engines: dict = field(default_factory=dict)     # engine -> {name: value}
    saved: dict = field(default_factory=dict)       # engine -> the file it saved
    valid: bool = True


def synthetic_trace(path):
    """A measured-looking trace on −360…359.3° in scrambled order (its own grid)."""
    angles = np.arange(-360.0, 360.0, 0.7)
    pressures = 0.1 + 4.5 * np.exp(-((angles - 12) / 28) ** 2) + 0.02 * np.cos(angles / 40)
    order = np.random.default_rng(7).permutation(len(angles))
    lines = ["crank angle [deg],pressure [MPa]"] + \
        [f"{float(angles[i])!r},{float(pressures[i])!r}" for i in order]
    path.write_text("\n".join(lines) + "\n")


def course_trace(path):
    angles = np.arange(0.0, 720.0, 2.0)
    path.write_text("\n".join(f"{a},{float(0.1 + 5 * np.exp(-((a - 370) / 25) ** 2))!r}"
                              for a in angles))


def bench_traces(path, speeds=(2000.0, 3500.0, 5000.0)):
    """A test bench's file: angle, then one pressure column per speed (r/min)."""
    angles = np.arange(0.0, 720.0, 1.0)
    rows = ["angle," + ",".join(f"{n:g}" for n in speeds)]
    rows += [",".join([f"{a:g}"] + [repr(float(0.1 + (2 + n / 1500) * np.exp(
        -((a - 370 - n / 1000) / 28) ** 2))) for n in speeds]) for a in angles]
    path.write_text("\n".join(rows) + "\n")


def build_all(tmp, workbooks=WORKBOOKS):
    files = {"trace": tmp / "trace.csv", "course_trace": tmp / "course_trace.csv",
             "bench": tmp / "bench.csv"}
    synthetic_trace(files["trace"])
    course_trace(files["course_trace"])
    bench_traces(files["bench"])
    paths = {}
    for name, entry in workbooks.items():
        path = tmp / f"{name}.xlsx"
        if "edit_of" in entry:
            edit_cells(paths[entry["edit_of"]], path, entry.get("edits", {}),
                       entry.get("tables"))
        else:
            args = [a.format(**{k: str(v) for k, v in files.items()}) for a in entry["args"]]
            done = run_cli("build", "-o", path, *args)
            assert done.returncode == 0, done.stderr
        paths[name] = path
    return paths


def recalculate_all(tmp, paths, workbooks=WORKBOOKS):
    """name -> Checked, with every file recalculated in every engine."""
    out = {}
    for name, path in paths.items():
        book, spec, template, ranges, values, tables, grids, sizes, rows = load_named(path)
        expected, floors = expected_values(spec, values, tables, grids, layout=rows)
        out[name] = Checked(path, spec, expected, floors, named(path),
                            valid=workbooks[name].get("valid", True))

    def engine_run(engine):
        # the values of every workbook (as verify reads them), then the few files the
        # tests of a saved workbook open; one engine start for ~40 workbooks takes longer
        # on a busy two-core machine than recalc's 600 s per-start guard for a hung engine
        computed = recalc.computed_values(list(paths.values()), tmp / engine,
                                          timeout=BATCH_TIMEOUT, engine=engine)
        saved = [name for name in SAVED[engine] if name in paths]
        files = recalc.convert([paths[name] for name in saved], tmp / engine / "saved",
                               timeout=BATCH_TIMEOUT, engine=engine) if saved else []
        return computed, dict(zip(saved, files))

    with ThreadPoolExecutor(max_workers=2) as pool:      # the engines on both cores
        runs = {engine: pool.submit(engine_run, engine) for engine in ENGINES}
        results = {engine: run.result() for engine, run in runs.items()}
    for engine, (computed, files) in results.items():
        for (name, path), values in zip(paths.items(), computed):
            out[name].engines[engine] = named_computed(path, values)
        for name, path in files.items():
            out[name].saved[engine] = path
    return out
