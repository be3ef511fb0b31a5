"""Every boundary value the rules allow either builds a workbook or gets one clear line.

For each preset and each numeric parameter: its bounds (or, where a bound is open,
values just inside it) through compute and to_excel.  Any exception other than a
CrankbookError with a one-line message is a failure.
"""
import numpy as np
import pytest

import crankbook
from crankbook.spec import params
from crankbook.errors import CrankbookError


TINY = (1e-300, 5e-324)             # the smallest positives a rule "> 0" allows


def boundary_values(parameter):
    """The bounds (closed), values just inside them (1e-12 and 1e-6 of the scale, and
    ·(1 ∓ 1e-9)), and the tiniest positives where the lower bound is 0."""
    out = []
    for bound, open_, inward in ((parameter.min, parameter.min_open, 1.0),
                                 (parameter.max, parameter.max_open, -1.0)):
        if bound is None:
            continue
        scale = max(abs(bound), 1.0)
        out += [bound + inward * scale * 1e-12, bound + inward * scale * 1e-6] if open_ \
            else [bound]
        if bound:
            out.append(bound * (1 + inward * 1e-9 * (1 if bound > 0 else -1)))
        if bound == 0 and inward > 0:
            out += list(TINY)
    return [v for v in out if not parameter.breaks_bounds(v)]


PRESETS = params.preset_names() if hasattr(params, "preset_names") else \
    ["thesis", "inline-4", "v8-crossplane", "course-design", "offset-optimization",
     "compressor", "boxer-4", "inline-3", "inline-6", "v-twin-90", "v6-60"]


def _cases():
    """(preset, key, value): every boundary value of every template's parameters, each
    on one of the presets of its template in turn — the bounds are the template's, so
    every value is tried once and every preset (layout) gets its share."""
    templates = {}
    for preset in PRESETS:
        templates.setdefault(params.load_preset(preset)[0].key, []).append(preset)
    out = []
    for presets in templates.values():
        spec = params.load_preset(presets[0])[0]
        values = [(p.key, v) for p in spec.parameters if p.kind == "number" and not p.axis
                  for v in boundary_values(p)]
        out += [(presets[i % len(presets)], key, value)
                for i, (key, value) in enumerate(values)]
    return out


CASES = _cases()


def _not_finite(result):
    """The keys holding a NaN or an infinity (a blank cell)."""
    return {k for k, v in result.results.items()
            if not np.all(np.isfinite(np.asarray(v, dtype=float)))}


WRITTEN = set()      # (template, blank results) written already: presets share templates


@pytest.mark.parametrize("preset", PRESETS)
def test_every_allowed_boundary_builds_or_says_why(preset, tmp_path):
    step = {"offset-optimization": None}.get(preset, 30.0)
    built = refused = 0
    default = crankbook.compute(preset, step=step)
    usual = _not_finite(default)      # blank by design
    template = default.spec.key
    for number, (_, key, value) in enumerate([c for c in CASES if c[0] == preset]):
        target = tmp_path / "b.xlsx"
        try:
            result = crankbook.compute(preset, step=step, **{key: value})
            # writing is where a non-finite number would fail: each new set of blank
            # results is written once per template, and each preset's first case
            blank = (template, frozenset(_not_finite(result) - usual))
            if number == 0 or (blank[1] and blank not in WRITTEN):
                result.to_excel(target)
                WRITTEN.add(blank)
            built += 1
        except CrankbookError as error:
            assert "\n" not in str(error) and len(str(error)) < 400, (key, value, error)
            assert not target.exists(), (key, value)
            refused += 1
        target.unlink(missing_ok=True)
    assert built >= 10                # the rules are not so tight that nothing builds
