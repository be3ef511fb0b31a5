"""crankbook: formula-backed Excel workbooks of piston-engine and compressor crank
trains, mechanisms, cams and gears.

The API (see the README's "Python API" section)::

    import crankbook
    results = crankbook.compute("thesis", speed=3000)      # numpy, sheet units
    results.series()                                        # pandas DataFrame
    results.to_excel("thesis.xlsx")                         # live formulas + charts
    crankbook.read("thesis.xlsx").scalars                   # back through the names
    crankbook.verify("thesis.xlsx")                         # LibreOffice vs numpy
"""
__version__ = "0.2.0"

from crankbook.errors import CrankbookError, CrankbookWarning  # noqa: E402
from crankbook.api import Results, compute, read, verify  # noqa: E402

__all__ = ["__version__", "CrankbookError", "CrankbookWarning", "Results", "compute", "read", "verify"]
