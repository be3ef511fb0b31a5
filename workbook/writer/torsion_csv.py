"""`crankbook export torsion WORKBOOK -o DIR` (and ``Results.to_torsion_csv``): the
equivalent system and the excitation as a torsional-vibration tool reads them; and
`crankbook export trace [WORKBOOK] -o FILE.csv`: a cylinder-pressure trace in the
format ``--pressure`` reads.

* ``stations.csv`` — station (1 = the front pulley, then one per throw, the last the
  flywheel), name, J [kg·m²], k [N·m/rad] of the shaft to the next station (blank
  for the last).
* ``harmonics.csv`` — cylinder, throw, order k, a_k and b_k [N·m]: cylinder i's
  torque M_i(α) = Σ a_k·cos(kα) + b_k·sin(kα) in the common crank angle α of
  cylinder 1 (its own harmonics turned by its firing angle φ_i: M_i(α) =
  M(α − φ_i + 360°)); then the same split into the gas part and the inertia part, and
  the speed they hold at (the workbook's design speed p_speed): at another speed n
  the gas part stays (the same pressure) and the inertia part scales with (n/p_speed)².
* ``response.csv`` — the forced, damped response over the workbook's speed sweep:
  speed [r/min], order k (or "synthesis", the sum of the orders' amplitudes), shaft
  section (1 = behind the pulley), elastic vibratory torque amplitude [N·m] and its
  shear stress 16·T·d/(π(d⁴ − d_b⁴)) in the main journal [MPa].

The numbers are the workbook's (read through its names, as stored), in the units
above; the files are UTF-8 with a byte-order mark (Excel then reads "·" and "²"
right; other tools skip it), and are written whole into DIR or not at all.
"""
import math

import numpy as np

from crankbook.support.atomic import atomic_path
from crankbook.support.csv_safety import csv_text
from crankbook.errors import BuildOptionError
from crankbook.support.workspace import check_output_folder, staged_directory
from crankbook.writer.exported import require_numbers

ENCODING = "utf-8-sig"
FILE_SUFFIXES = (".csv", ".xlsx", ".txt", ".json")


def _turned(a, b, k, delta):
    """(a, b) of order k of a series shifted by ``delta`` [rad]."""
    c, s = math.cos(k * delta), math.sin(k * delta)
    return float(a * c - b * s), float(a * s + b * c)


def rows(results):
    """(stations rows, harmonics rows) of a Results (computed or read)."""
    needed = ("station_inertia", "section_stiffness", "torque_order", "cylinder_torque_cosine",
              "cylinder_torque_sine", "cylinder_inertia_torque_cosine",
              "cylinder_inertia_torque_sine")
    missing = [k for k in needed if k not in results.results]
    if missing:
        raise BuildOptionError(f"export torsion: the workbook has no {missing[0]} (an engine "
                               f"workbook built by this crankbook has)")
    require_numbers(results, ("station_inertia", "cylinder_torque_cosine"), "export torsion")
    inertia = np.atleast_1d(np.asarray(results["station_inertia"], dtype=float))
    stiffness = np.atleast_1d(np.asarray(results["section_stiffness"], dtype=float))
    stations = [["station", "name", "J [kg·m²]", "k to next [N·m/rad]"]]
    for number, value in enumerate(inertia, start=1):
        name = "pulley" if number == 1 else "flywheel" if number == inertia.size \
            else f"throw {number - 1}"
        stations.append([number, name, float(value),
                         float(stiffness[number - 1]) if number < inertia.size else ""])
    orders = np.atleast_1d(np.asarray(results["torque_order"], dtype=float))
    a = np.atleast_1d(np.asarray(results["cylinder_torque_cosine"], dtype=float))
    b = np.atleast_1d(np.asarray(results["cylinder_torque_sine"], dtype=float))
    a_j = np.atleast_1d(np.asarray(results["cylinder_inertia_torque_cosine"], dtype=float))
    b_j = np.atleast_1d(np.asarray(results["cylinder_inertia_torque_sine"], dtype=float))
    firing = np.atleast_1d(np.asarray(results.parameters["firing_angle"], dtype=float))
    throw = np.atleast_1d(np.asarray(results.parameters["throw"], dtype=float))
    speed = float(results.parameters["speed"])
    harmonics = [["cylinder", "throw", "order", "a_k [N·m]", "b_k [N·m]", "a_k gas [N·m]",
                  "b_k gas [N·m]", "a_k inertia [N·m]", "b_k inertia [N·m]",
                  "at speed [r/min]"]]
    for cylinder, (phi, t) in enumerate(zip(firing, throw), start=1):
        delta = math.radians(phi - 360.0)
        for k, ak, bk, akj, bkj in zip(orders, a, b, a_j, b_j):
            total = _turned(ak, bk, k, delta)
            inertial = _turned(akj, bkj, k, delta)
            gas = _turned(ak - akj, bk - bkj, k, delta)
            harmonics.append([cylinder, int(t), float(k), *total, *gas, *inertial, speed])
    return stations, harmonics


def response_rows(results):
    """The rows of response.csv (module docstring) of a Results."""
    needed = ("sweep_speed", "response_order", "response_speed", "response_section_torque",
              "section_torque", "section_stress")
    missing = [k for k in needed if k not in results.results]
    if missing:
        raise BuildOptionError(f"export torsion: the workbook has no {missing[0]} (an engine "
                               f"workbook built by this crankbook has)")
    require_numbers(results, ("sweep_speed", "response_section_torque"), "export torsion")
    d = float(results.parameters["main_journal_diameter"])
    bore = float(results.parameters["main_journal_bore"])
    factor = 16 * 1000 * d / (math.pi * (d ** 4 - bore ** 4))    # N·m -> MPa, d in mm
    order = np.ravel(np.asarray(results["response_order"], dtype=float))
    speed = np.ravel(np.asarray(results["response_speed"], dtype=float))
    torque = np.asarray(results["response_section_torque"], dtype=float).reshape(order.size, -1)
    out = [["speed [r/min]", "order", "section", "torque amplitude [N·m]", "stress [MPa]"]]
    sweep = np.ravel(np.asarray(results["sweep_speed"], dtype=float))
    synthesis = np.asarray(results["section_torque"], dtype=float).reshape(sweep.size, -1)
    stress = np.asarray(results["section_stress"], dtype=float).reshape(sweep.size, -1)
    for s, n in enumerate(sweep):
        if not math.isfinite(n):
            continue
        for row in range(24 * s, 24 * s + 24):
            if math.isfinite(order[row]) and math.isfinite(speed[row]):
                for j, t in enumerate(torque[row], start=1):
                    out.append([float(speed[row]), float(order[row]), j, float(t),
                                float(t * factor)])
        for j, (t, tau) in enumerate(zip(synthesis[s], stress[s]), start=1):
            out.append([float(n), "synthesis", j, float(t), float(tau)])
    return out


def _folder(directory):
    """-o of `export torsion` is a folder: a name like x.csv is a slip, refused."""
    if str(directory).lower().endswith(FILE_SUFFIXES):
        raise BuildOptionError(f"-o {directory}: export torsion writes three files "
                               f"(stations.csv, harmonics.csv, response.csv) into a folder; give a folder "
                               f"name, not a file name")
    return directory


def write(results, directory, source=None):
    """Write stations.csv, harmonics.csv and response.csv into ``directory`` (replaced whole, if an
    earlier export wrote it; ``source``, the workbook read, is never inside it)."""
    stations, harmonics = rows(results)
    response = response_rows(results)
    check_output_folder(_folder(directory), "export torsion", [(source, False)])
    with staged_directory(directory, replace=True, command="export torsion") as staging:
        (staging / "stations.csv").write_text(csv_text(stations), encoding=ENCODING,
                                              newline="")
        (staging / "harmonics.csv").write_text(csv_text(harmonics), encoding=ENCODING,
                                               newline="")
        (staging / "response.csv").write_text(csv_text(response), encoding=ENCODING,
                                              newline="")
    return directory


def write_trace(results, path):
    """Write the cylinder pressure of ``results`` as a trace file: crank angle [°],
    absolute pressure [MPa], one row a grid point of one cycle (the format
    ``--pressure`` reads)."""
    from crankbook.writer.build import check_output
    if "cylinder_pressure" not in results.results:
        raise BuildOptionError("export trace: the workbook has no cylinder_pressure (an "
                               "engine workbook has)")
    require_numbers(results, ("cylinder_pressure",), "export trace")
    path = check_output(path, ".csv")
    angle = np.asarray(results["crank_angle"], dtype=float)
    pressure = np.asarray(results["cylinder_pressure"], dtype=float)
    inside = angle < results.spec.cycle - 1e-9
    table = [["crank angle [deg]", "pressure [MPa]"]] + \
        [[float(x), round(float(p), 6)] for x, p in zip(angle[inside], pressure[inside])]
    with atomic_path(path) as temporary:
        with open(temporary, "w", encoding=ENCODING, newline="") as handle:
            handle.write(csv_text(table))
    return path
