"""The engine over its speed range: operating points from the design-speed workbook.

Every force on the crank train is the gas force plus the reciprocating inertia
force, and everything downstream (side, rod, tangential and radial forces, torques,
crank-pin and main-bearing loads, the pin's bending and torsion) is linear in them.
The inertia force and the centrifugal forces grow with ω², so at the speed n_k of
operating point k each such quantity is

    X_k(α) = G_c(α) + s_k·J(α),    s_k = (n_k/n)²,

with J(α) its inertia part at the design speed n and G_c(α) its gas part for the
cylinder pressure c of point k: one pressure for every speed (the model, or one
trace: c = 1), or the measured trace of each speed (c = k).  The functions here
compute G and J and the per-point extremes from them; the tests compare every
point with a workbook computed from scratch at that speed.

Shapes: a series (N + 1,), a per-case series (N + 1, C), a per-throw (journal)
series (N + 1, T); a block of a throw (journal) × case product axis (N + 1, T·C) with
the throw counting fastest.  SI units, angles in radians, as everywhere in calc/.

References
----------
Thesis 000 §3.1–3.2 (the forces), §4.6 (the pin as a beam); any engine-dynamics text
for the superposition of gas and inertia forces.
"""
import numpy as np

from crankbook.calc import crankshaft, cycle, multicylinder


# ---------------------------------------------------------------- points and cases
def case_count(operating_trace_count, pressure_source=0.0, heat_release_source=1.0,
               combustion_timing=1.0, operating_speed=(0.0,)):
    """Cylinder pressures of the operating points: one per measured trace; one per point
    where the model's heat (the charge, ``heat_release_source`` 2) or its combustion
    angles (the table, ``combustion_timing`` 2) follow the speed; else one (the
    workbook's cylinder pressure) for every speed."""
    traces = int(round(float(operating_trace_count)))
    if traces > 0:
        return traces
    follows_speed = round(float(heat_release_source)) == 2 or round(float(combustion_timing)) == 2
    if round(float(pressure_source)) == 0 and follows_speed:
        return max(1, int(np.size(operating_speed)))
    return 1


def pressure_from(operating_trace_count, pressure_source, operating_speed,
                  heat_release_source=1.0, combustion_timing=1.0):
    """Where each point's cylinder pressure comes from: 0 the Pressure sheet's, the same
    at every speed; 1 its own measured trace; 2 the model at the point's own speed
    (P,)."""
    if float(pressure_source) == 1:
        value = 0.0 if int(round(float(operating_trace_count))) == 0 else 1.0
    else:
        cases = case_count(operating_trace_count, pressure_source, heat_release_source,
                           combustion_timing, operating_speed)
        value = 2.0 if cases > 1 else 0.0
    return np.full(np.size(operating_speed), value)


def cases_stale(pressure_source, heat_release_source, combustion_timing, operating_speed):
    """1 when a workbook laid out with one pressure for every speed now asks for one per
    point (its heat or combustion angles switched to follow the speed), else 0.  The
    layout numpy evaluates always follows the inputs, so 0 here; the workbook's own
    cell says 1 after such an edit."""
    del pressure_source, heat_release_source, combustion_timing, operating_speed
    return 0.0


def inertia_scale(operating_speed, speed):
    """s_k = (ω_k/ω)² of each point: how much larger its inertia forces are [-]."""
    return (np.asarray(operating_speed, dtype=float) / speed) ** 2


def _columns(values):
    """The columns of a per-case series (N + 1, C), or a series (N + 1,) as one."""
    values = np.asarray(values, dtype=float)
    return [values] if values.ndim == 1 else [values[:, c] for c in range(values.shape[1])]


def _for_points(case_values, points):
    """The per-case columns (N + 1, C) as one column per point (N + 1, P): point k
    takes case k, or the one case of a pressure that is the same at every speed."""
    values = np.asarray(case_values, dtype=float)
    values = values.reshape(values.shape[0], -1)
    if values.shape[1] == 1:
        return np.repeat(values, points, axis=1)
    return values[:, :points]


def _blocks_for_points(case_block, items, points):
    """A (N + 1, T·C) block as a list of P arrays (N + 1, T), one per point."""
    block = np.asarray(case_block, dtype=float)
    cases = block.shape[1] // items
    return [block[:, (0 if cases == 1 else k) * items:((0 if cases == 1 else k) + 1) * items]
            for k in range(points)]


# ---------------------------------------------------------------- the pressure of each case
def case_pressure(operating_trace_count, pressure_source, cylinder_pressure,
                  operating_model_pressure, operating_measured_pressure):
    """The cylinder pressure of each case (N + 1, C) [Pa]: a measured trace
    (``pressure_source`` 1) — the Pressure sheet's at every speed, or each speed's own
    — else each case's model pressure (the point's heat and combustion angles; the same
    as the Pressure sheet's where they do not change with speed)."""
    measured = np.asarray(operating_measured_pressure, dtype=float)
    model = np.asarray(operating_model_pressure, dtype=float)
    if float(pressure_source) != 1:
        return model
    if int(round(float(operating_trace_count))) == 0:
        return np.broadcast_to(np.asarray(cylinder_pressure, dtype=float).reshape(-1, 1),
                               model.shape)
    return measured


# ---------------------------------------------------------------- gas and inertia parts
def each_cylinder(case_values, crank_angle, firing_angle, cycle):
    """A per-case single-cylinder series read at each cylinder's own crank angle
    α − φ_i + 360° (N + 1, n·C), the cylinder counting fastest."""
    return np.hstack([multicylinder.cylinder_series(column, crank_angle, firing_angle, cycle)
                      for column in _columns(case_values)])


def on_throws(block, throw):
    """Σ over the cylinders on each throw of a cylinder × case block (N + 1, T·C)."""
    block = np.asarray(block, dtype=float)
    cylinders = np.size(throw)
    return np.hstack([crankshaft.per_throw(block[:, c * cylinders:(c + 1) * cylinders], throw)
                      for c in range(block.shape[1] // cylinders)])


def on_throws_radial(block, throw, throw_rods, big_end_mass, crank_radius, angular_velocity):
    """The radial pin load's inertia part: Σ over each throw's cylinders of the radial
    inertia force, less each big end's centrifugal m2·r·ω² (N + 1, T) [N]."""
    return on_throws(block, throw) - np.asarray(throw_rods, dtype=float) * big_end_mass \
        * crank_radius * angular_velocity ** 2


def throw_crank_angle(crank_angle_of_throw, throw):
    """θ_t at α = 0 of each throw: the crank angle of its first cylinder (they all agree:
    a rule), 0 for a throw number no cylinder uses (T,) [rad]."""
    angles = np.asarray(crank_angle_of_throw, dtype=float)
    throw = np.asarray(throw, dtype=float)
    out = np.zeros(multicylinder.throw_count(throw))
    for t in range(out.size):
        on = np.flatnonzero(throw == t + 1)
        out[t] = angles[on[0]] if on.size else 0.0
    return out


def throw_crank_force(cylinder_rotating_force, big_end_mass, crank_radius, angular_velocity,
                      throw):
    """The outward centrifugal force of each throw beyond its rods' big ends: the crank's
    unbalanced mass less the counterweight (T,) [N]."""
    return crankshaft.per_throw(np.asarray(cylinder_rotating_force, dtype=float)
                                - big_end_mass * crank_radius * angular_velocity ** 2, throw)


def torque_of_throws(block, throw, before, crank_radius):
    """r·Σ of the throws' tangential loads (the engine torque), or of the throws ahead
    of throw ``before`` (the torque of the journal in front of it; 0: all throws), per
    case of a throw × case block (N + 1, C) [N·m]."""
    block = np.asarray(block, dtype=float)
    throws = multicylinder.throw_count(throw)
    limit = throws if float(before) == 0 else int(round(float(before))) - 1
    return block.reshape(block.shape[0], -1, throws)[:, :, :limit].sum(axis=2) * crank_radius


def journal_load_of_throws(tangential, radial, outward, crank_angle, throw_crank_angle, throw,
                           component):
    """Each main journal's bearing load from its two neighbouring throws, half each,
    in the engine frame: x = P_t·cosθ + (F_out − P_r)·sinθ, y = −P_t·sinθ + (F_out −
    P_r)·cosθ with θ = α + θ_t, P_t, P_r the throw's crank-pin loads (crank frame,
    radial toward the centre) and F_out its outward centrifugal force; ``component``
    0 gives x, 1 gives y (N + 1, (T + 1)·C) or (N + 1, T + 1) [N]."""
    tangential = np.asarray(tangential, dtype=float)
    throws = multicylinder.throw_count(throw)
    theta = np.asarray(crank_angle, dtype=float).reshape(-1, 1) + \
        np.asarray(throw_crank_angle, dtype=float).reshape(1, -1)
    parts = []
    for c in range(tangential.shape[1] // throws):
        columns = slice(c * throws, (c + 1) * throws)
        t = tangential[:, columns]
        out = np.asarray(outward, dtype=float) - np.asarray(radial, dtype=float)[:, columns]
        load = t * np.cos(theta) + out * np.sin(theta) if float(component) == 0 \
            else -t * np.sin(theta) + out * np.cos(theta)
        parts.append(crankshaft._journal_share(load, np.arange(1.0, throws + 1)))
    return np.hstack(parts)


def throw_of_cases(case_block, throw, check_throw):
    """Throw ``check_throw``'s column of each case of a throw × case block (N + 1, C)."""
    block = np.asarray(case_block, dtype=float)
    throws = multicylinder.throw_count(throw)
    item = int(round(float(check_throw))) - 1
    return block[:, item::throws]


# ---------------------------------------------------------------- extremes per point
def peak_of_case(values, inertia_scale):
    """max |G_c| of each point's case (P,)."""
    return np.abs(_for_points(values, np.size(inertia_scale))).max(axis=0)


def peak_scaled(values, inertia_scale):
    """s_k·max |J| of each point (P,)."""
    return np.asarray(inertia_scale, dtype=float) * np.abs(np.asarray(values, dtype=float)).max()


def _combined(gas, inertia, inertia_scale):
    """G_c + s_k·J of each point (N + 1, P)."""
    scale = np.asarray(inertia_scale, dtype=float)
    return _for_points(gas, scale.size) + scale[None, :] * np.asarray(inertia, dtype=float) \
        .reshape(-1, 1)


def peak(gas, inertia, inertia_scale):
    """max |G_c + s_k·J| of each point (P,)."""
    return np.abs(_combined(gas, inertia, inertia_scale)).max(axis=0)


def peak_side_force(operating_gas_force, inertia_force, inertia_scale, rod_angle):
    """max |(Fg_c + s_k·Fj)·tanβ| of each point (P,) [N]."""
    return np.abs(_combined(operating_gas_force, inertia_force, inertia_scale)
                  * np.tan(np.asarray(rod_angle, dtype=float)).reshape(-1, 1)).max(axis=0)


def peak_rod_force(operating_gas_force, inertia_force, inertia_scale, rod_angle):
    """max |(Fg_c + s_k·Fj)/cosβ| of each point (P,) [N]."""
    return np.abs(_combined(operating_gas_force, inertia_force, inertia_scale)
                  / np.cos(np.asarray(rod_angle, dtype=float)).reshape(-1, 1)).max(axis=0)


def torque_maximum(gas, inertia, inertia_scale):
    """max (M_gas,c + s_k·M_inertia) of the engine torque at each point (P,) [N·m]."""
    return _combined(gas, inertia, inertia_scale).max(axis=0)


def torque_minimum(gas, inertia, inertia_scale):
    """min (M_gas,c + s_k·M_inertia) of each point (P,) [N·m]."""
    return _combined(gas, inertia, inertia_scale).min(axis=0)


def torque_mean(gas, inertia, inertia_scale):
    """Cycle mean of M_gas,c plus s_k times the cycle mean of M_inertia (closing point
    left out) (P,) [N·m]."""
    scale = np.asarray(inertia_scale, dtype=float)
    return _for_points(gas, scale.size)[:-1].mean(axis=0) \
        + scale * np.asarray(inertia, dtype=float)[:-1].mean()


def power(mean_torque, angular_velocity):
    """M_mean,k·ω_k of each point (P,) [W]."""
    return np.asarray(mean_torque, dtype=float) * np.asarray(angular_velocity, dtype=float)


def largest_load(gas_x, inertia_x, gas_y, inertia_y, inertia_scale):
    """max over the grid and the throws (journals) of |(Gx + s·Jx, Gy + s·Jy)| of each
    point (P,) [N]."""
    scale = np.asarray(inertia_scale, dtype=float)
    items = np.asarray(inertia_x).shape[1]
    out = []
    for k, (gx, gy) in enumerate(zip(_blocks_for_points(gas_x, items, scale.size),
                                     _blocks_for_points(gas_y, items, scale.size))):
        out.append(np.hypot(gx + scale[k] * np.asarray(inertia_x, dtype=float),
                            gy + scale[k] * np.asarray(inertia_y, dtype=float)).max())
    return np.array(out)


def _pin_stresses(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                  gas_journal_torque, inertia_journal_torque, inertia_scale, crank_radius,
                  throw_span, pin_bending_modulus, pin_torsion_modulus):
    tangential = _combined(gas_tangential, inertia_tangential, inertia_scale)
    radial = _combined(gas_radial, inertia_radial, inertia_scale)
    torque = _combined(gas_journal_torque, inertia_journal_torque, inertia_scale)
    bending = np.hypot(crankshaft.pin_bending_stress_component(radial, throw_span,
                                                               pin_bending_modulus),
                       crankshaft.pin_bending_stress_component(tangential, throw_span,
                                                               pin_bending_modulus))
    torsion = crankshaft.torsional_stress(
        crankshaft.pin_torque(torque, tangential, crank_radius), pin_torsion_modulus)
    return bending, torsion


def pin_bending_extreme(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                        gas_journal_torque, inertia_journal_torque, inertia_scale,
                        crank_radius, throw_span, pin_bending_modulus, pin_torsion_modulus,
                        largest):
    """The largest (``largest`` 1) or smallest resultant bending stress of the checked
    pin over the cycle at each point (P,) [Pa]."""
    bending, _ = _pin_stresses(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                               gas_journal_torque, inertia_journal_torque, inertia_scale,
                               crank_radius, throw_span, pin_bending_modulus,
                               pin_torsion_modulus)
    return bending.max(axis=0) if largest else bending.min(axis=0)


def pin_torsion_extreme(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                        gas_journal_torque, inertia_journal_torque, inertia_scale,
                        crank_radius, throw_span, pin_bending_modulus, pin_torsion_modulus,
                        largest):
    """The largest or smallest torsional stress of the checked pin at each point (P,)
    [Pa]."""
    _, torsion = _pin_stresses(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                               gas_journal_torque, inertia_journal_torque, inertia_scale,
                               crank_radius, throw_span, pin_bending_modulus,
                               pin_torsion_modulus)
    return torsion.max(axis=0) if largest else torsion.min(axis=0)


def pin_combined_maximum(gas_tangential, inertia_tangential, gas_radial, inertia_radial,
                         gas_journal_torque, inertia_journal_torque, inertia_scale,
                         crank_radius, throw_span, pin_bending_modulus, pin_torsion_modulus,
                         strength_theory):
    """The largest combined stress of the checked pin over the cycle at each point, by
    the 3rd or 4th strength theory (P,) [Pa]."""
    bending, torsion = _pin_stresses(gas_tangential, inertia_tangential, gas_radial,
                                     inertia_radial, gas_journal_torque,
                                     inertia_journal_torque, inertia_scale, crank_radius,
                                     throw_span, pin_bending_modulus, pin_torsion_modulus)
    return crankshaft.combined_stress(bending, torsion, strength_theory).max(axis=0)


def traces_mismatch(operating_trace_count, operating_speed, operating_trace_pressure):
    """1 when per-speed traces are given but not one for each operating point, else 0."""
    count = int(round(float(operating_trace_count)))
    columns = np.shape(operating_trace_pressure)[-1] if np.ndim(operating_trace_pressure) == 2 \
        else 1
    return float(count > 0 and (count != np.size(operating_speed) or count != columns))


def trace_speed_mismatch(pressure_source, trace_speed, speed):
    """1 when the measured trace in use was recorded at another speed than the design
    speed (``trace_speed`` 0: not stated, never a mismatch), else 0."""
    return float(round(float(pressure_source)) == 1 and trace_speed > 0 and trace_speed != speed)


def point_trace_speed_mismatch(pressure_source, operating_trace_count, operating_trace_speed,
                               operating_speed):
    """1 when some operating point's own measured trace was recorded at another speed
    than the point's, else 0 (always 0 where the points share one pressure)."""
    speeds = np.atleast_1d(np.asarray(operating_speed, dtype=float))
    recorded = np.broadcast_to(np.atleast_1d(np.asarray(operating_trace_speed, dtype=float)),
                               speeds.shape)
    per_point = round(float(pressure_source)) == 1 and round(float(operating_trace_count)) > 0
    return float(per_point and np.any((recorded > 0) & (recorded != speeds)))


# ---------------------------------------------------------------- the points' own cycle
def point_imep(case_pressure, cylinder_volume, displaced_volume, operating_speed):
    """IMEP = ∮p·dV/V_d of each point's cylinder pressure (trapezoidal over the closed
    cycle) (P,) [Pa]."""
    columns = _for_points(case_pressure, np.size(operating_speed))
    return np.array([cycle.indicated_work(columns[:, k], cylinder_volume)
                     for k in range(columns.shape[1])]) / displaced_volume


def point_maximum(case_values, operating_speed):
    """The largest value of each point's case over the cycle (P,)."""
    return _for_points(case_values, np.size(operating_speed)).max(axis=0)
