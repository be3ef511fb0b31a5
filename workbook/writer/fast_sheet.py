"""A worksheet that skips xlsxwriter's per-formula rewriting of future functions.

xlsxwriter runs ~30 regular expressions over every formula to prefix Excel 2010+
"future" and dynamic-array functions with _xlfn.  crankbook's templates use none of
them (spec.check refuses them: the workbooks must open in Excel 2010, LibreOffice
and WPS), so the rewriting is pure cost — most of a build's time.
"""
from xlsxwriter.worksheet import Worksheet


class FastWorksheet(Worksheet):
    def _prepare_formula(self, formula, expand_future_functions=False):
        if formula.startswith("{"):
            formula = formula[1:]
        if formula.startswith("="):
            formula = formula[1:]
        if formula.endswith("}"):
            formula = formula[:-1]
        return formula
