"""Where things go: sheet names in the chosen language, series columns and rows."""
from workbook.formulas import Locator

FIRST_ROW = 5            # 0-based row of the first grid point on every series sheet
OTHER = {"zh": "en", "en": "zh"}
FIXED_SHEETS = {"parameters": {"zh": "参数", "en": "Parameters"},
                "summary": {"zh": "汇总", "en": "Summary"}}


def label(item, lang, attr=""):
    """The zh or en text of a spec item (``attr`` prefix such as 'title_')."""
    return getattr(item, f"{attr}{lang}")


def unit_text(unit):
    return {"deg": "°", "-": "–"}.get(unit, unit)


class Layout:
    def __init__(self, spec, lang, grid_sizes, table_lengths=None):
        """``grid_sizes``: grid key -> number of rows."""
        self.spec = spec
        self.lang = lang
        self.other = OTHER[lang]
        self.sheet_name = {key: names[lang] for key, names in FIXED_SHEETS.items()}
        for sheet in spec.sheets:
            self.sheet_name[sheet.key] = label(sheet, lang)
        # The first sheet on a grid holds its values; others refer to them.
        self.master = {}
        for sheet in spec.sheets:
            if sheet.kind == "series":
                self.master.setdefault(sheet.grid, sheet.key)
        columns = {grid: (self.sheet_name[home], 0, grid) for grid, home in self.master.items()}
        self.table_start = {}
        self.table_capacity = {t.key: max(t.capacity, (table_lengths or {}).get(t.key, 0))
                               for t in spec.input_tables}
        for sheet in spec.sheets:
            if sheet.kind != "series":
                continue
            for index, column in enumerate(sheet.columns, start=1):
                columns[column.key] = (self.sheet_name[sheet.key], index, sheet.grid)
        for table in spec.input_tables:
            sheet = next(s for s in spec.sheets if s.key == table.sheet)
            self.table_start[table.key] = len(sheet.columns) + 2
        grid_rows = {g: (FIRST_ROW, FIRST_ROW + n - 1) for g, n in grid_sizes.items()}
        self.locator = Locator(spec, columns, grid_rows)
        self.defined_names = {}   # name -> reference, filled by the sheet writers

    def last_row(self, grid):
        return self.locator.grid_rows[grid][1]

    def tables_on(self, sheet_key):
        return [t for t in self.spec.input_tables if t.sheet == sheet_key]
