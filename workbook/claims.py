"""Document claims (templates/claims/*.toml) and their recomputation.

Each claim is a number a source document states, with the inputs it depends on,
the recomputation as an Excel formula template ({input} placeholders) and as a
Python expression over the same inputs in the document's units (the expression
may call calc/ through the helpers below), a tolerance, and a note.  Kinds:

* ``value``        — the document's number against the recomputation (mismatch)
* ``consistency``  — against another statement of the same document (inconsistent)
* ``range``        — a dimension against the design-rule range the document quotes;
                     the recomputation is the nearest value inside the range
* ``unverifiable`` — the document gives too little; the note says what is missing
"""
import math
from dataclasses import dataclass, field

import numpy as np

import re

from crankbook.calc import (cam, compressor, crankshaft, cycle, forces, gears, kinematics,
                            mechanism, multicylinder, optimization)
from crankbook.toml_files import names_in, read_named

CLAIMS = "claims"
INPUT = re.compile(r"\{([A-Za-z_][A-Za-z_0-9]*)\}")      # {name} of a claim's input
STATUS_OF_KIND = {"value": "mismatch", "consistency": "inconsistent", "range": "mismatch"}
DEFAULT_TOLERANCE = 0.005          # relative: documents print 3–4 significant digits

HELPERS = {
    "__builtins__": {}, "abs": abs, "min": min, "max": max, "round": round, "sum": sum,
    "pi": math.pi, "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "radians": math.radians,
    "degrees": math.degrees, "log10": math.log10, "exp": math.exp,
    "np": np, "kinematics": kinematics, "forces": forces, "mechanism": mechanism,
    "optimization": optimization, "cycle": cycle, "multicylinder": multicylinder,
    "gears": gears, "cam": cam, "compressor": compressor, "crankshaft": crankshaft,
}


@dataclass
class Claim:
    key: str
    section: str
    claim: str
    unit: str
    reported: float | None = None      # None where the extraction lost the number
    kind: str = "value"
    inputs: dict = field(default_factory=dict)
    formula: str | None = None
    python: str | None = None
    tolerance: float = DEFAULT_TOLERANCE
    abs_tolerance: float = 0.0
    note: str = ""

    def recompute(self):
        """The recomputed value in the document's unit, or None (unverifiable)."""
        if self.kind == "unverifiable" or self.python is None:
            return None
        return float(eval(self.python, HELPERS, dict(self.inputs)))  # noqa: S307 (our data)

    def status(self, recomputed):
        if recomputed is None or self.reported is None:
            return "unverifiable"
        limit = max(self.tolerance * abs(recomputed), self.abs_tolerance)
        return "ok" if abs(self.reported - recomputed) <= limit else STATUS_OF_KIND[self.kind]


@dataclass
class Document:
    key: str
    file: str
    title: str
    claims: list

    def findings(self):
        out = []
        for claim in self.claims:
            recomputed = claim.recompute()
            out.append({"document": self.key, "section": claim.section, "claim": claim.claim,
                        "reported": claim.reported, "unit": claim.unit,
                        "recomputed": recomputed, "status": claim.status(recomputed),
                        "note": claim.note, "key": claim.key})
        return out


def document_names():
    return names_in(CLAIMS)


def load(name):
    data = read_named(CLAIMS, name, "document", extra_choices=["all"])
    head = data["document"]
    claims = [Claim(**entry) for entry in data.get("claim", [])]
    seen = set()
    for claim in claims:
        if claim.key in seen:
            raise ValueError(f"{name}: claim key {claim.key!r} twice")
        seen.add(claim.key)
        if claim.kind not in (*STATUS_OF_KIND, "unverifiable"):
            raise ValueError(f"{name}: claim {claim.key!r} has unknown kind {claim.kind!r}")
        for ref in INPUT.findall(claim.formula or ""):
            if ref not in claim.inputs:
                raise ValueError(f"{name}: formula of {claim.key!r} uses unknown {ref!r}")
    return Document(key=head["key"], file=head["file"], title=head["title"], claims=claims)
