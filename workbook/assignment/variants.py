"""Per-student parameters: drawn reproducibly from the template's ranges, rounded as a
teacher would print them, each a valid mechanism that passes every check the
assignment lists (cams above their smallest base radius, no undercut, no pointed
tooth, …), no two alike.

A student's draw depends only on the seed and their id, so adding a student
changes nobody else's task and the same roster and seed give the same files.  The
seed is therefore the class's secret: crankbook is public, and a student who knows
it draws their own key.  A small seed is found by trying seeds until one draws the
task the student was given, so the default is a random one (``secret_seed``).
"""
import collections
import hashlib
import secrets

import numpy as np

from crankbook.spec import evaluate

from crankbook.spec import params
from crankbook.support.arithmetic import ArithmeticError_, evaluate as arithmetic
from crankbook.errors import CrankbookError, SpecError

MAX_ATTEMPTS = 500
GUESSABLE_SEED = 10 ** 12      # below this a student's computer tries every seed in days


def secret_seed():
    """A random seed of 18 digits: too many to try, short enough to copy."""
    return 10 ** 17 + secrets.randbelow(9 * 10 ** 17)


def guessable(seed):
    """True for a seed a student could find by trying seeds against their own task."""
    return abs(seed) < GUESSABLE_SEED


def student_rng(seed, student_id):
    digest = hashlib.sha256(f"{seed}:{student_id}".encode()).digest()
    return np.random.default_rng(int.from_bytes(digest[:8], "big"))


def _choice(value):
    """A drawn choice as the workbook takes it: a number, a list (a per-item
    parameter: teeth of each gear), or a word (a motion law) left for validate."""
    if isinstance(value, (list, tuple)):
        return [float(v) for v in value]
    return value if isinstance(value, str) else float(value)


def _draw(assignment, base, rng, fixed=None):
    values = dict(base)
    formulas = {}
    fixed = fixed or {}
    for key, rule in assignment.variant.items():
        if key in fixed:
            rng.random()          # the draw keeps its pace: a group changes no other value
            continue
        if "choices" in rule:
            # ``with``: companion parameters drawn at the same index (a gear train's
            # teeth and the profile shifts that keep its small gear from undercutting)
            index = int(rng.integers(len(rule["choices"])))
            values[key] = _choice(rule["choices"][index])
            for other, options in rule.get("with", {}).items():
                values[other] = _choice(options[index])
        elif "formula" in rule:
            formulas[key] = rule
        else:
            count = int(round((rule["max"] - rule["min"]) / rule["step"]))
            values[key] = round(rule["min"] + rule["step"] * int(rng.integers(count + 1)), 6)
    values.update(fixed)
    for key, rule in formulas.items():
        try:
            value = arithmetic(rule["formula"], values)
        except ArithmeticError_ as error:
            raise SpecError(f"assignments/{assignment.key}.toml", key, str(error)) from None
        values[key] = round(round(value / rule["step"]) * rule["step"], 6)
    return values


def rejection(assignment, spec, values):
    """Why the parameters make no mechanism the assignment can use (a phrase), or None
    when they do."""
    # only what the checks below read, and what that needs
    checks = [k for k in assignment.constraints.get("checks", ()) if k in spec.quantity]
    wanted = [q.key for q in spec.quantities() if q.must_pass] + checks + \
        [k for k in ("min_transmission_angle", "raw_crank_angle") if k in spec.quantity]
    try:
        values = params.validate(spec, dict(values))
        out = evaluate.evaluate(spec, values, {}, evaluate.crank_angle_grid(spec, 30.0),
                                keys=wanted)
    except CrankbookError as error:
        return str(error)
    for q in spec.quantities():
        if q.must_pass and np.any(np.asarray(out[q.key], dtype=float) == 0):
            return f"{q.key} fails"            # e.g. a roller that undercuts the cam
    for k in checks:
        if not np.all(np.asarray(out[k], dtype=float) == 1):
            return f"{k} fails"                # a check of the workbook (r0 < r0min, …)
    bound = assignment.constraints.get("min_transmission_angle")
    if bound is not None and out.get("min_transmission_angle", 90.0) < bound:
        return (f"the smallest transmission angle {float(out['min_transmission_angle']):.1f}° "
                f"is below {bound:g}°")
    share = assignment.constraints.get("rows_in_motion")
    if share is not None:
        still = _rows_at_rest(assignment, spec, values, share)
        if still:
            return still
    separation = assignment.constraints.get("min_position_separation")
    if separation is not None and "raw_crank_angle" in out:
        angles = np.sort(np.asarray(out["raw_crank_angle"]) % 360)
        gaps = np.diff(np.concatenate([angles, [angles[0] + 360]]))
        if gaps.min() < separation:
            # answers are placed by their crank angle: two positions this close could
            # be taken for each other
            return (f"two of the 15 positions lie {gaps.min():.2f}° apart (at least "
                    f"{separation:g}°, min_position_separation)")
    return None


def _rows_at_rest(assignment, spec, values, share):
    """Why a row asked at a listed angle (a cam angle) would pay for typing zero — a
    value below ``share`` of its largest over the cycle: a dwell, the middle of a rise
    where a cosine or cycloidal law's acceleration vanishes — or None."""
    for grid, angles in assignment.row_angles.items():
        items = [k for sheet in assignment.sheets if sheet.rows == grid for k in sheet.items
                 if k in spec.quantity]
        if not items:
            continue
        fine = np.union1d(np.arange(0.0, 360.0, 1.0), np.asarray(angles, float))
        rows = np.searchsorted(fine, np.asarray(angles, float))
        try:
            with np.errstate(all="ignore"):
                out = evaluate.evaluate(spec, values, {}, {**evaluate.build_grids(spec),
                                                           grid: fine}, keys=items)
        except CrankbookError as error:
            return str(error)
        for key in items:
            series = np.abs(np.asarray(out[key], dtype=float))
            if series.shape != fine.shape:
                continue
            low = series[rows] < share * np.nanmax(series)
            if np.any(low):
                return (f"{key} is (nearly) zero at the asked {grid.replace('_', ' ')} "
                        f"{angles[int(np.argmax(low))]:g}° (rows_in_motion)")
    return None


def fingerprint(values, keys):
    text = ";".join(f"{k}={values[k]!r}" for k in keys)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def draw_class(assignment, spec, base, student_ids, seed, fixed=None):
    """student_id -> parameter values, reproducible for the same ids and seed;
    ``fixed``: student_id -> values every draw of that student keeps (their group's)."""
    out, used = {}, set()
    keys = sorted(assignment.variant)
    for sid in student_ids:
        rng = student_rng(seed, sid)
        reasons = collections.Counter()
        for _ in range(MAX_ATTEMPTS):
            values = _draw(assignment, base, rng, (fixed or {}).get(sid))
            values.update({k: params.coerce(spec.parameter[k], v) for k, v in values.items()
                           if isinstance(v, str)})          # a law's word: its index
            mark = fingerprint(values, keys)
            reason = "the same set as another student's" if mark in used else \
                rejection(assignment, spec, values)
            if reason is None:
                used.add(mark)
                out[sid] = values
                break
            reasons[reason] += 1
        else:
            group = fixed.get(sid) if fixed else None
            alone = group and rejection(assignment, spec, {**base, **group})
            if alone:             # the group's row decides it: no draw can help
                raise CrankbookError(
                    f"{sid!r}: the values of their group (" + ", ".join(
                        f"{k} = {v:g}" for k, v in group.items()
                        if isinstance(v, (int, float))) + f") make no usable mechanism: {alone}")
            raise CrankbookError(f"could not draw a valid, distinct parameter set for {sid!r} "
                                 f"in {MAX_ATTEMPTS} attempts (mostly: "
                                 f"{reasons.most_common(1)[0][0]}); widen the template's ranges")
    return out
