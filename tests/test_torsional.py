"""Torsional vibration (issue 28, the calc layer): Holzer's table against closed forms
and the generalised eigenvalues, the equivalent inertia against seed 004's ring mass,
Carter's length by its scaling, and the vector sums against the classic major orders
of the presets' firing orders (Den Hartog, Mechanical Vibrations, §5.8)."""
import numpy as np
import pytest

from crankbook.spec import params
from crankbook.calc import multicylinder, torsional

HOLZER_REL = 2e-4          # linear interpolation on a 0.05 Hz grid, relative to f


def test_two_rotors_have_the_closed_form_frequency():
    J1, J2, k = 0.8, 2.5, 4.0e5                               # kg·m², N·m/rad
    closed = np.sqrt(k * (J1 + J2) / (J1 * J2)) / (2 * np.pi)
    assert torsional.natural_frequencies([J1, J2], [k]) == pytest.approx([closed], rel=1e-12)
    found = torsional.holzer_frequencies([J1, J2], [k], 0.05, 200.0)
    assert found == pytest.approx([closed], rel=HOLZER_REL)
    # the node divides the shaft in the ratio J2 : J1, so θ2 = −J1/J2
    shape = torsional.mode_shapes([closed], [J1, J2], [k])[:, 0]
    assert shape == pytest.approx([1.0, -J1 / J2], rel=1e-9)


def test_three_rotors_match_the_quadratic_in_omega_squared():
    J1, J2, J3, k1, k2 = 0.3, 1.2, 0.7, 2.0e5, 3.5e5
    a = J1 * J2 * J3
    b = -(k1 * J3 * (J1 + J2) + k2 * J1 * (J2 + J3))
    c = k1 * k2 * (J1 + J2 + J3)
    omega2 = np.sort(np.roots([a, b, c]).real)
    closed = np.sqrt(omega2) / (2 * np.pi)
    assert torsional.natural_frequencies([J1, J2, J3], [k1, k2]) == pytest.approx(closed,
                                                                                  rel=1e-10)
    found = torsional.holzer_frequencies([J1, J2, J3], [k1, k2], 0.05, 400.0)
    assert found == pytest.approx(closed, rel=HOLZER_REL)


@pytest.mark.parametrize("seed", range(6))
def test_holzer_finds_every_eigenfrequency_of_a_chain(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 11))
    inertia = rng.uniform(0.01, 0.5, n)
    stiffness = rng.uniform(2e4, 4e5, n - 1)
    eigen = torsional.natural_frequencies(inertia, stiffness)
    top = eigen[-1] * 1.05
    found = torsional.holzer_frequencies(inertia, stiffness, top / 20000, top)
    assert found == pytest.approx(eigen, rel=HOLZER_REL)
    # the one- and two-node modes (the ones an engine meets) have one and two sign
    # changes; higher modes of a random chain localise, and Holzer's forward
    # recurrence cannot resolve amplitudes of 1e-7 at the far end
    shapes = torsional.mode_shapes(eigen[:2], inertia, stiffness)
    for mode in range(shapes.shape[1]):
        signs = np.sign(shapes[:, mode])
        assert np.count_nonzero(signs[1:] != signs[:-1]) == mode + 1, mode


def test_a_grid_below_the_first_mode_finds_nothing():
    assert torsional.holzer_frequencies([1.0, 1.0], [1.0e4], 0.1, 5.0).size == 0


def test_a_throws_station_is_its_rods_ring_mass_at_the_crank_radius():
    """A throw's J = m_big·r² + m_j·r²·(1/2 + λ²/8) + J_web: the reciprocating mass by
    its mean over a turn, which is seed 004's bob weight (the ring mass) at r; and the
    ring mass is the kinetic-energy mean computed numerically."""
    m_j, m_big, lam, r, web = 0.62, 0.41, 0.29, 0.045, 0.002
    ring = multicylinder.ring_mass_per_rod(m_j, m_big, lam)
    stations = torsional.station_inertias(0.1, [ring, 2 * ring], r, web, 0.5)
    textbook = m_big * r ** 2 + m_j * r ** 2 * (0.5 + lam ** 2 / 8) + web
    assert stations[1] == pytest.approx(textbook, rel=1e-12)
    assert stations[2] == pytest.approx(2 * (textbook - web) + web, rel=1e-12)   # two rods
    numeric = multicylinder.ring_mass_numeric(m_j, m_big, lam) * r ** 2 + web
    assert stations[1] == pytest.approx(numeric, rel=1e-3)
    assert (stations[0], stations[-1]) == (0.1, 0.5)


def test_carter_length_scales_with_the_crank_and_reduces_to_a_plain_shaft():
    dims = dict(journal_diameter=0.06, journal_length=0.03, pin_diameter=0.05,
                pin_length=0.028, web_thickness=0.018, web_width=0.09, crank_radius=0.045)
    base = torsional.carter_equivalent_length(**dims)
    scaled = torsional.carter_equivalent_length(**{k: 2.5 * v for k, v in dims.items()})
    assert scaled == pytest.approx(2.5 * base, rel=1e-12)          # a length
    # a pin as thick as the journal and a stiff web leave journal and pin in series
    plain = dict(dims, pin_diameter=0.06, web_width=1e3)
    assert torsional.carter_equivalent_length(**plain) == pytest.approx(
        0.03 + 0.8 * 0.018 + 0.75 * 0.028, rel=1e-9)
    k = torsional.shaft_stiffness(80e9, 0.06, base)
    assert k == pytest.approx(80e9 * np.pi * 0.06 ** 4 / 32 / base, rel=1e-12)


@pytest.mark.parametrize("preset", ["inline-4", "v8-crossplane"])
def test_stations_sections_and_orders_are_named_for_what_they_are(tmp_path, preset):
    """An engineer reads "the stress peaks in section 6": the stations are named front,
    throw by throw, flywheel (as many throws as the layout has), each section by the
    main journal it holds (as many as the main-bearing sheet's journals), and a column
    of torque order k says k — the order's value, not its place in the list (order 0.5
    is the first)."""
    import zipfile

    import openpyxl
    from crankbook import compute
    result = compute(preset, step=30)
    path = result.to_excel(tmp_path / "engine.xlsx", lang="en")
    book = openpyxl.load_workbook(path)
    throws = int(max(result.values["throw"]))
    stations = [c.value for c in book["Torsional stations"]["A"][5:] if c.value]
    assert stations == ["Front pulley/damper", *(f"Throw {k}" for k in range(1, throws + 1)),
                        "Flywheel"]
    journals = [c.value for c in book["Main bearings"]["A"][5:] if c.value]
    sections = [c.value for c in book["Section stresses"]["A"][5:] if c.value]
    assert len(sections) == len(journals) == throws + 1
    assert sections == [f"Section {j.split()[-1]} (journal {j.split()[-1]})" for j in journals]
    with zipfile.ZipFile(path) as z:                    # … and so do the charts' legends
        charts = "".join(z.read(n).decode() for n in z.namelist() if "charts/chart" in n)
    assert all(charts.count(f">{name}<") >= 2 for name in sections)     # torque, stress
    orders = np.ravel(result.results["torque_order"])
    headers = [c.value for c in book["Torsional stress"][3]
               if isinstance(c.value, str) and c.value.startswith("Front amplitude (per order)")]
    assert [h.rsplit("k = ", 1)[1] for h in headers] == [f"{k:g}" for k in orders]
    assert orders[0] == 0.5


@pytest.mark.parametrize("preset,major", [("inline-4", 2.0), ("inline-6", 3.0),
                                          ("v8-crossplane", 4.0)])
def test_the_firing_order_excites_its_major_orders(preset, major):
    """With equal amplitudes at every cylinder (the first mode of a stiff short
    crankshaft), the vector sum is the cylinder count at the major orders — multiples
    of n/2 for a four-stroke engine — and vanishes at every other order."""
    spec, values, _ = params.load_preset(preset)
    phases = np.radians(np.asarray(values["firing_angle"], dtype=float))
    n = phases.size
    sums = torsional.relative_amplitude_sum(np.ones((n, 1)), phases)[:, 0]
    for k, total in zip(torsional.ORDERS, sums):
        if abs(k / major - round(k / major)) < 1e-12:
            assert total == pytest.approx(n, rel=1e-12), (preset, k)
        else:
            assert total == pytest.approx(0.0, abs=1e-9), (preset, k)


def test_critical_speeds_are_sixty_f_over_k():
    speeds = torsional.critical_speeds([150.0, 420.0], orders=(0.5, 3.0, 6.0))
    assert speeds.shape == (3, 2)
    assert speeds[1] == pytest.approx([3000.0, 8400.0])
    assert speeds[0, 0] == pytest.approx(18000.0)


# ---------------------------------------------------------------- in the workbooks
ENGINE_PRESETS = [p for p in params.preset_names()
                  if params.load_preset(p)[0].key == "engine"]


@pytest.mark.parametrize("preset", ENGINE_PRESETS)
def test_every_engine_workbooks_holzer_frequencies_are_its_eigenfrequencies(preset):
    import crankbook
    r = crankbook.compute(preset, step=30.0)
    J, k = r["station_inertia"], r["section_stiffness"]
    assert J.size == r["station_count"] == k.size + 1
    eigen = torsional.natural_frequencies(J, k)
    found = np.asarray(r["natural_frequency"], dtype=float)
    top = min(r.parameters["holzer_step"] * torsional.HOLZER_ROWS,
              r.parameters["holzer_max_frequency"])
    within = eigen[eigen < top - r.parameters["holzer_step"]]
    assert within.size >= 1, (preset, eigen[:2])           # the first mode is on the grid
    # linear interpolation between grid points: within 0.5 % of the eigenvalue
    assert found[:within.size] == pytest.approx(within, rel=5e-3), preset
    assert np.all(np.isnan(found[within.size:]))             # no mode beyond the grid


def test_typed_inertias_and_a_stiffer_shaft_move_the_frequencies():
    import crankbook
    base = crankbook.compute("inline-4", step=30.0)
    stiff = crankbook.compute("inline-4", step=30.0, main_journal_diameter=70.0)
    heavy = crankbook.compute("inline-4", step=30.0, flywheel_inertia_typed=0.5,
                              web_inertia=0.004)
    assert stiff["natural_frequency"][0] > base["natural_frequency"][0]
    assert heavy["natural_frequency"][0] < base["natural_frequency"][0]
    assert heavy["station_inertia"][-1] == 0.5
    eigen = torsional.natural_frequencies(heavy["station_inertia"],
                                          heavy["section_stiffness"])
    assert heavy["natural_frequency"][0] == pytest.approx(eigen[0], rel=5e-3)


def test_critical_speeds_are_flagged_inside_the_operating_speeds():
    import crankbook
    r = crankbook.compute("inline-6", step=30.0, main_journal_diameter=32.0)
    f = np.asarray(r["natural_frequency"], dtype=float)
    c = np.asarray(r["critical_speed"], dtype=float)
    k = np.asarray(r["torsion_order"], dtype=float)
    assert np.allclose(c[:, :1] * k[:, None] / 60, f[:1], rtol=1e-12)     # n = 60 f / k
    speeds = np.asarray(r.parameters["operating_speed"], dtype=float)
    inside = (c >= speeds.min()) & (c <= speeds.max())
    assert np.array_equal(np.asarray(r["critical_in_range"]) == 1, inside)
    assert inside.any() and not inside.all()      # this shaft meets some orders in range


def test_the_export_carries_the_system_and_harmonics_that_sum_to_the_engine(tmp_path):
    """stations.csv is the workbook's system; the cylinders' harmonics in the common
    crank angle add up, order by order, to the engine torque's amplitude."""
    import csv
    import crankbook
    from tests.conftest import run_cli
    path = crankbook.compute("v8-crossplane", step=6.0).to_excel(tmp_path / "v8.xlsx")
    done = run_cli("export", "torsion", path, "-o", tmp_path / "tv")
    assert done.returncode == 0, done.stderr
    back = crankbook.read(path)
    with open(tmp_path / "tv" / "stations.csv", newline="", encoding="utf-8-sig") as f:
        stations = list(csv.DictReader(f))
    assert [float(r["J [kg·m²]"]) for r in stations] == pytest.approx(
        list(back["station_inertia"]), rel=1e-12)
    assert stations[0]["name"] == "pulley" and stations[-1]["k to next [N·m/rad]"] == ""
    with open(tmp_path / "tv" / "harmonics.csv", newline="", encoding="utf-8-sig") as f:
        harmonics = list(csv.DictReader(f))
    for k, amplitude in zip(back["torque_order"], back["engine_torque_amplitude"]):
        parts = [complex(float(r["a_k [N·m]"]), float(r["b_k [N·m]"])) for r in harmonics
                 if float(r["order"]) == k]
        assert len(parts) == 8
        assert abs(sum(parts)) == pytest.approx(amplitude, rel=1e-6, abs=1e-6 * max(
            back["engine_torque_amplitude"]))
    # the gas and inertia parts add up to the total; the inertia part is the inertia
    # torque's harmonic at the speed the file states
    assert {float(r["at speed [r/min]"]) for r in harmonics} == {back.parameters["speed"]}
    for r in harmonics:
        for part in ("a_k", "b_k"):
            assert float(r[f"{part} gas [N·m]"]) + float(r[f"{part} inertia [N·m]"]) == \
                pytest.approx(float(r[f"{part} [N·m]"]), abs=1e-9 * max(
                    back["engine_torque_amplitude"]))
    first = [r for r in harmonics if r["cylinder"] == "1"]
    assert [float(r["a_k inertia [N·m]"]) for r in first] == pytest.approx(
        list(back["cylinder_inertia_torque_cosine"]), abs=1e-9)
    with open(tmp_path / "tv" / "harmonics.csv", "rb") as f:
        assert f.read(3) == b"\xef\xbb\xbf"               # Excel reads the "·" right
    assert "at 5000 r/min" in done.stdout
    done = run_cli("export", "torsion", tmp_path / "nothing.xlsx", "-o", tmp_path / "x")
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    done = run_cli("export", "torsion", path, "-o", tmp_path / "x.csv")
    assert done.returncode == 2 and "give a folder name" in done.stderr
    assert not (tmp_path / "x.csv").exists()


def test_an_exported_trace_builds_the_engine_it_came_from(tmp_path):
    """export trace writes a workbook's pressure in the format --pressure reads: built
    from it, the engine's indicated power is the one the trace came from."""
    import crankbook
    from tests.conftest import run_cli
    done = run_cli("export", "trace", "-o", tmp_path / "measured.csv")
    assert done.returncode == 0, done.stderr
    model = crankbook.compute("thesis")
    measured = crankbook.compute("thesis", pressure=tmp_path / "measured.csv")
    assert measured.scalars["indicated_power"] == pytest.approx(
        model.scalars["indicated_power"], rel=1e-5)
    done = run_cli("export", "trace", "-o", tmp_path / "measured.xlsx")
    assert done.returncode == 2 and "must end in .csv" in done.stderr


@pytest.mark.parametrize("preset", ["thesis", "inline-4", "inline-6", "v8-crossplane"])
def test_the_workbooks_mode_shapes_are_the_eigenvectors(preset):
    """Each found mode's column is the generalised eigenvector of K·v = ω²·J·v,
    scaled so the pulley's amplitude is 1 (to the Holzer grid's interpolation)."""
    import crankbook
    r = crankbook.compute(preset, step=30.0)
    J, k = r["station_inertia"], r["section_stiffness"]
    n = J.size
    K = np.diag(np.r_[k, 0.0] + np.r_[0.0, k]) - np.diag(k, 1) - np.diag(k, -1)
    omega2, vectors = np.linalg.eig(np.linalg.solve(np.diag(J), K))
    order = np.argsort(omega2.real)
    shapes = np.asarray(r["mode_shape"], dtype=float)
    assert shapes.shape == (n, n - 1)
    for mode in range(n - 1):
        if np.isnan(r["natural_frequency"][mode]):
            assert np.all(np.isnan(shapes[:, mode]))
            continue
        v = vectors[:, order[mode + 1]].real
        assert shapes[:, mode] == pytest.approx(v / v[0], abs=2e-2), (preset, mode)
        modal = float(np.sum(J * shapes[:, mode] ** 2))
        assert r["modal_inertia"][mode] == pytest.approx(modal, rel=1e-12)


@pytest.mark.parametrize("preset,major", [("inline-4", 2.0), ("inline-6", 3.0)])
def test_at_a_major_order_every_cylinder_adds_in_phase(preset, major):
    """The workbook's vector sum at a major order is the plain sum of the mode's
    amplitudes at the throws; at every order it is at most the sum of their sizes."""
    import crankbook
    r = crankbook.compute(preset, step=30.0)
    beta = np.asarray(r["mode_shape"], dtype=float)[1:-1, 0]          # the throws
    sums = np.asarray(r["relative_amplitude_sum"], dtype=float)[:, 0]
    for k, total in zip(r["torsion_order"], sums):
        assert total <= np.sum(np.abs(beta)) * (1 + 1e-12)
        if abs(k / major - round(k / major)) < 1e-12:
            assert total == pytest.approx(abs(beta.sum()), rel=1e-12), k


def test_the_resonant_amplitude_is_the_damped_forced_response():
    """The energy balance's θ_1 against the steady response of the damped chain, solved
    directly: (K − ω²·J + j·ω·C)·x = F at ω = ω_1, with C = 2·ζ·ω_1·J (the mass-
    proportional damping whose first mode has the ratio ζ) and each cylinder's order-k
    torque at its throw with its firing phase.  Light damping: the resonant mode
    dominates, and the two agree within the other modes' share."""
    import crankbook
    zeta = 0.005
    r = crankbook.compute("inline-6", step=10.0, torsion_damping_ratio=zeta)
    J, k = r["station_inertia"], r["section_stiffness"]
    K = np.diag(np.r_[k, 0.0] + np.r_[0.0, k]) - np.diag(k, 1) - np.diag(k, -1)
    f1 = torsional.natural_frequencies(J, k)[0]
    omega = 2 * np.pi * f1
    for row, order in enumerate(r["torsion_order"]):
        if order not in (3.0, 6.0, 1.5):
            continue
        amplitude = r["resonant_torque_amplitude"][row, 0]     # at the critical speed
        phases = np.radians(np.asarray(r.parameters["firing_angle"], dtype=float))
        F = np.zeros(J.size, dtype=complex)
        for throw, phase in zip(r.parameters["throw"], phases):
            F[int(throw)] += amplitude * np.exp(1j * order * phase)
        x = np.linalg.solve(K - omega ** 2 * np.diag(J) + 1j * omega * 2 * zeta * omega *
                            np.diag(J), F)
        expected = np.degrees(abs(x[0]))
        assert r["resonant_amplitude"][row, 0] == pytest.approx(expected, rel=0.03), order


def test_the_exciting_torque_is_the_harmonic_at_the_critical_speed():
    """The order-k torque driving a resonance is one cylinder's harmonic at the critical
    speed: the same engine computed at that speed gives it (gas torque unchanged, the
    inertia torque with the speed squared) — with a pressure that does not follow the
    speed: the resonance table takes the design speed's gas torque, and says so."""
    import crankbook
    held = {"heat_release_source": "typed", "combustion_timing": "fixed"}
    r = crankbook.compute("inline-6", step=10.0, **held)
    orders = list(r["torque_order"])
    for row, order in enumerate(r["torsion_order"]):
        if order not in (3.0, 4.5, 6.0):
            continue
        speed = r["critical_speed"][row, 0]
        there = crankbook.compute("inline-6", step=10.0, speed=speed, **held)
        expected = there["cylinder_torque_amplitude"][orders.index(order)]
        assert r["resonant_torque_amplitude"][row, 0] == pytest.approx(expected, rel=1e-9)
        if order == 3.0:                # the inertia torque has whole orders: 3 differs
            assert expected != pytest.approx(
                r["cylinder_torque_amplitude"][orders.index(order)], rel=0.01)


def test_typed_values_must_fill_the_stations():
    import crankbook
    from crankbook.errors import LayoutError
    typed = crankbook.compute("thesis", station_inertia_typed=[0, 0, 2.0],
                              section_stiffness_typed=[1e5, 0])
    assert typed["station_inertia"][-1] == 2.0 and typed["section_stiffness"][0] == 1e5
    with pytest.raises(LayoutError, match="station_inertia_typed has 2 values, one per "
                                          "station: this workbook has 3"):
        crankbook.compute("thesis", station_inertia_typed=[0, 0])


def test_the_highest_trial_frequency_ends_the_grid():
    """Rows beyond p_holzer_max_frequency are blank and find nothing: the inline-6's
    second mode (≈ 1020 Hz) is found on the full grid and not below 600 Hz."""
    import crankbook
    full = crankbook.compute("inline-6", step=30.0)
    short = crankbook.compute("inline-6", step=30.0, holzer_max_frequency=600.0)
    grid = np.asarray(short["holzer_frequency"], dtype=float)
    assert np.nanmax(grid) == 600.0 and np.isnan(grid[200:]).all()
    assert np.isnan(short["holzer_amplitude"][200:]).all()
    assert short["natural_frequency"][0] == full["natural_frequency"][0]
    assert not np.isnan(full["natural_frequency"][1]) and np.isnan(short["natural_frequency"][1])


def test_thomsons_holzer_table_row_by_row():
    """Thomson & Dahleh, *Theory of Vibration with Applications*, 5th ed., Example
    12.4-1 and Table 12.4-1: J = 5, 11, 22 kg·m², K = 0.10·10⁶, 0.20·10⁶ N·m/rad,
    trial ω = 20 and 40 rad/s; the printed amplitudes and torques to their printed
    digits (4 significant figures)."""
    J, K = [5.0, 11.0, 22.0], [0.10e6, 0.20e6]
    printed = {20.0: ([1.0, 0.980, 0.9484], [2.0e3, 6.312e3, 14.66e3]),
               40.0: ([1.0, 0.920, 0.799], [8.0e3, 24.19e3, 52.32e3])}
    for omega, (theta, torque) in printed.items():
        amplitude, shaft = torsional.holzer(omega, J, K)
        assert amplitude[0] == pytest.approx(theta, abs=6e-4), omega
        assert shaft[0] == pytest.approx(torque, rel=6e-4), omega


def test_a_modes_columns_are_headed_by_the_mode(tmp_path):
    """The sections and modes share one count; a critical speed, a vector sum or a mode
    shape belongs to a mode, and its header and legend say so ("Mode 2"), never
    "Section / mode 2"; the shared rows say both."""
    import openpyxl
    from crankbook import compute
    path = compute("inline-4", step=30).to_excel(tmp_path / "i4.xlsx", lang="en")
    book = openpyxl.load_workbook(path)
    headers = [c.value for ws in (book["Critical speeds"], book["Mode shapes"])
               for row in ws.iter_rows(max_row=6) for c in row
               if isinstance(c.value, str) and " — " in c.value]
    assert headers and all(h.rsplit(" — ", 1)[1].startswith(("Mode ", "振型 "))
                           for h in headers)           # the header's two languages
    rows = [c.value for c in book["Sections, frequencies"]["A"] if isinstance(c.value, str)]
    assert "Section 1 (journal 1) / mode 1" in rows     # the shared rows name both


@pytest.mark.parametrize("preset,major", [("inline-4", 2.0), ("inline-6", 3.0),
                                          ("v8-crossplane", 4.0), ("inline-3", 1.5)])
def test_the_campbell_diagram_draws_every_order_of_the_critical_speed_table(preset, major):
    """A four-stroke engine's torque has half orders: the diagram draws k = 0.5 … 12
    (it drew 1 … 12, so an inline-3's 1.5 resonance was in the table and not on the
    diagram), and marks as major exactly the multiples of n/2."""
    import crankbook
    r = crankbook.compute(preset, step=30.0)
    speeds = np.asarray(r["campbell_speed"], dtype=float)
    lines = np.asarray(r["campbell_order_line"], dtype=float)
    orders = lines[-1] * 60 / speeds[-1]                  # f = k·n/60 at the top speed
    assert orders == pytest.approx(np.asarray(r["torsion_order"], dtype=float), rel=1e-12)
    assert orders.size == 24 and orders[[0, -1]] == pytest.approx([0.5, 12], rel=1e-12)
    orders = np.round(orders * 2) / 2
    expected = [2 if abs(k / major - round(k / major)) < 1e-12 else 1 if k == round(k) else 0
                for k in orders]
    assert list(r["major_order"]) == expected
    # each resonance of the table is a crossing on the diagram: the order line reaches
    # the mode's frequency at the table's critical speed
    for i, k in enumerate(orders):
        for mode, f in enumerate(np.asarray(r["natural_frequency"], dtype=float)[:3]):
            if np.isfinite(f):
                n_c = r["critical_speed"][i][mode]
                assert np.interp(n_c, speeds, lines[:, i]) == pytest.approx(f, rel=1e-9) \
                    or n_c > speeds[-1]


def test_the_operating_box_spans_the_operating_speeds():
    import crankbook
    r = crankbook.compute("inline-6", step=30.0)
    x, y = np.asarray(r["operating_box_speed"]), np.asarray(r["operating_box_frequency"])
    low, high = min(r.parameters["operating_speed"]), max(r.parameters["operating_speed"])
    assert list(x[:5]) == [low, low, high, high, low] and set(x[5:]) == {low}
    top = 12 * max(r["campbell_speed"]) / 60
    assert list(y[:5]) == pytest.approx([0, top, top, 0, 0]) and not y[5:].any()


@pytest.mark.parametrize("speed", [1000.0, 4500.0])
def test_the_flywheel_is_a_part_not_a_function_of_the_speed(speed):
    """The preset's flywheel is sized once (at its design speed): the torsional model's
    frequencies do not move when only p_speed changes.  Sized at p_speed instead (0
    typed), a low speed makes a flywheel no engine has, and the check says so."""
    import crankbook
    base = crankbook.compute("inline-6", step=30.0)
    moved = crankbook.compute("inline-6", step=30.0, speed=speed)
    assert moved["natural_frequency"][:2] == pytest.approx(base["natural_frequency"][:2],
                                                           rel=1e-12)
    assert moved.scalars["flywheel_implausible"] == 0
    sized = crankbook.compute("inline-6", step=30.0, speed=1000.0, flywheel_inertia_typed=0)
    assert sized.scalars["flywheel_implausible"] == 1
