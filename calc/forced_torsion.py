"""Forced, damped torsional vibration of the crankshaft's equivalent system.

The chain of stations of :mod:`crankbook.calc.torsional` (inertias J_i, shaft
stiffnesses k_i), now with damping and a harmonic excitation of one engine order q at
circular frequency ω = q·Ω:

* each shaft section is a complex stiffness k*_i = k_i·(1 + i·η) + i·ω·c_i, η the loss
  factor of the shaft (hysteretic: its damping torque is η·k_i·Δθ whatever the
  frequency) and c_i a viscous coupling (a damper's ring to its hub);
* each station may have an absolute viscous damper to ground, c_g,i, and an exciting
  torque F_i (complex amplitude: the order-q harmonic of the torque acting there);

and the steady response θ_i·e^(iωt) satisfies, with Holzer's sign convention (T_i the
torque in section i, behind station i, T_0 = 0),

    T_i = T_(i−1) + (ω²·J_i − i·ω·c_g,i)·θ_i + F_i,    θ_(i+1) = θ_i − T_i/k*_i,

and a free back end, T_n = 0.  The recurrence is linear in θ_1, so two passes — one
with θ_1 = 1 and no excitation, one with θ_1 = 0 and the excitation — give residuals
R_1, R_2 and the front amplitude θ_1 = −R_2/R_1: a spreadsheet does the same, row by
row, in real and imaginary columns, with no matrix inverse.  :func:`direct_response`
solves (K* − ω²J + iωC)θ = F with numpy as the independent check.

Units: J in kg·m², k in N·m/rad, c in N·m·s/rad, ω in rad/s, torques in N·m, angles in
radians, stresses in Pa, diameters in m (mm where a rule says so).

References
----------
Den Hartog, J. P., *Mechanical Vibrations*, 4th ed., McGraw-Hill, 1956: §3.3 (the
damped vibration absorber: the tuned optimum f = 1/(1 + μ), ζ = √(3μ/(8(1 + μ)³))),
§5.6 (Holzer), §5.9 (the untuned viscous damper: ζ_opt = 1/√(2(1 + μ)(2 + μ)), the
peak 1 + 2/μ).
Mendes, A. S., Meirelles, P. S. and Zampieri, D. E., "Analysis of torsional vibration
in internal combustion engines: modelling and experimental validation", Proc. IMechE
Part K 222 (2008) 155–178: an MWM six-cylinder diesel whose Fig. 31 (the flywheel
section's vibratory torque against speed) the tests reproduce through this module,
with the model, damping and digitised curves of the openTorsion project's
reproduction (tests/data/mendes_2008.toml).
IACS UR M68, "Dimensions of propulsion shafts and their permissible torsional
vibration stresses", Rev. 2, 2005: τ_C = ±(σ_B + 160)/18·C_K·C_D·(3 − 2λ²) for
λ < 0.9, ·1.38 for 0.9 ≤ λ ≤ 1.05, τ_T = 1.7·τ_C/√C_K, C_D = 0.35 + 0.93·d^−0.2.
"""
import numpy as np


# ---------------------------------------------------------------- the recurrence
def section_complex_stiffness(stiffness, angular_frequency, loss_factor=0.0,
                              section_damping=0.0):
    """k* = k·(1 + i·η) + i·ω·c of each section [N·m/rad] (complex)."""
    k = np.asarray(stiffness, dtype=float)
    return k * (1 + 1j * np.asarray(loss_factor, dtype=float)) \
        + 1j * angular_frequency * np.asarray(section_damping, dtype=float)


def holzer_pass(angular_frequency, inertia, complex_stiffness, front_amplitude,
                excitation, ground_damping):
    """One pass of the forced recurrence from the front: the station amplitudes θ (n,)
    and the residual torque T_n behind the last station (complex)."""
    inertia = np.asarray(inertia, dtype=float)
    n = inertia.size
    excitation = np.broadcast_to(np.asarray(excitation, dtype=complex), (n,))
    ground = np.broadcast_to(np.asarray(ground_damping, dtype=float), (n,))
    theta = np.zeros(n, dtype=complex)
    theta[0] = front_amplitude
    torque = 0j
    for i in range(n):
        torque = torque + (angular_frequency ** 2 * inertia[i]
                           - 1j * angular_frequency * ground[i]) * theta[i] + excitation[i]
        if i < n - 1:
            theta[i + 1] = theta[i] - torque / complex_stiffness[i]
    return theta, torque


def forced_response(angular_frequency, inertia, stiffness, excitation, loss_factor=0.0,
                    section_damping=0.0, ground_damping=0.0):
    """Steady complex amplitudes θ_i [rad] of every station under the excitation F_i
    [N·m] at ω [rad/s], by the two-pass recurrence (module docstring)."""
    k_star = section_complex_stiffness(stiffness, angular_frequency, loss_factor,
                                       section_damping)
    free, residual_free = holzer_pass(angular_frequency, inertia, k_star, 1.0, 0.0,
                                      ground_damping)
    forced, residual_forced = holzer_pass(angular_frequency, inertia, k_star, 0.0,
                                          excitation, ground_damping)
    return -residual_forced / residual_free * free + forced


def direct_response(angular_frequency, inertia, stiffness, excitation, loss_factor=0.0,
                    section_damping=0.0, ground_damping=0.0):
    """The same amplitudes from (K* − ω²J + iωC_g)θ = F, solved with numpy [rad]."""
    inertia = np.asarray(inertia, dtype=float)
    n = inertia.size
    k_star = section_complex_stiffness(stiffness, angular_frequency, loss_factor,
                                       section_damping)
    matrix = np.zeros((n, n), dtype=complex)
    for i, k in enumerate(np.broadcast_to(k_star, (n - 1,))):
        matrix[i, i] += k
        matrix[i + 1, i + 1] += k
        matrix[i, i + 1] -= k
        matrix[i + 1, i] -= k
    matrix -= np.diag(angular_frequency ** 2 * inertia)
    matrix += np.diag(1j * angular_frequency
                      * np.broadcast_to(np.asarray(ground_damping, dtype=float), (n,)))
    return np.linalg.solve(matrix, np.broadcast_to(np.asarray(excitation, dtype=complex), (n,)))


def section_torque(theta, stiffness):
    """The elastic vibratory torque of each section k_i·(θ_i − θ_(i+1)) (complex) [N·m]."""
    theta = np.asarray(theta)
    return np.asarray(stiffness, dtype=float) * (theta[:-1] - theta[1:])


# ---------------------------------------------------------------- stresses and limits
def section_shear_stress(torque, diameter, bore=0.0):
    """τ = 16·T·d_o/(π·(d_o⁴ − d_b⁴)) of a hollow round section [Pa]."""
    d = np.asarray(diameter, dtype=float)
    return 16 * np.asarray(torque, dtype=float) * d / (np.pi * (d ** 4 - np.asarray(bore) ** 4))


def m68_size_factor(diameter):
    """C_D = 0.35 + 0.93·d^−0.2, d the shaft diameter in mm (IACS UR M68) [-]."""
    return 0.35 + 0.93 * (np.asarray(diameter, dtype=float) * 1000) ** -0.2


def m68_continuous_limit(tensile_strength, shape_factor, diameter, speed_ratio):
    """τ_C of IACS UR M68 for continuous running [Pa]: (σ_B + 160)/18·C_K·C_D·(3 − 2λ²)
    below λ = 0.9, ·1.38 from 0.9 to 1.05 (and above, the value at 1.05); σ_B in Pa
    enters the rule's formula in N/mm²."""
    sigma = np.asarray(tensile_strength, dtype=float) / 1e6
    base = (sigma + 160) / 18 * shape_factor * m68_size_factor(diameter)
    ratio = np.asarray(speed_ratio, dtype=float)
    return np.where(ratio < 0.9, base * (3 - 2 * ratio ** 2), base * 1.38) * 1e6


def m68_transient_limit(continuous_limit, shape_factor):
    """τ_T = 1.7·τ_C/√C_K, for passing a barred speed range quickly [Pa]."""
    return 1.7 * np.asarray(continuous_limit, dtype=float) / np.sqrt(shape_factor)


# ---------------------------------------------------------------- Den Hartog's optima
def untuned_damper_optimum_ratio(mass_ratio):
    """ζ_opt = c/(2·J_d·ω_n) = 1/√(2(1 + μ)(2 + μ)) of an untuned viscous (Lanchester)
    damper, μ = J_d/J (Den Hartog §5.9) [-]."""
    mu = np.asarray(mass_ratio, dtype=float)
    return 1 / np.sqrt(2 * (1 + mu) * (2 + mu))


def untuned_damper_peak(mass_ratio):
    """The peak amplification 1 + 2/μ with the optimum untuned damper [-]."""
    return 1 + 2 / np.asarray(mass_ratio, dtype=float)


def tuned_absorber_frequency_ratio(mass_ratio):
    """f = ω_a/ω_n = 1/(1 + μ) of the optimum tuned absorber (Den Hartog §3.3) [-]."""
    return 1 / (1 + np.asarray(mass_ratio, dtype=float))


def tuned_absorber_damping_ratio(mass_ratio):
    """ζ_opt = √(3μ/(8(1 + μ)³)) of the optimum tuned absorber [-]."""
    mu = np.asarray(mass_ratio, dtype=float)
    return np.sqrt(3 * mu / (8 * (1 + mu) ** 3))
