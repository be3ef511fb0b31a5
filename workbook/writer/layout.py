"""Where things go: sheet names in the chosen language and the series columns."""
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
    def __init__(self, spec, lang, grid_size, table_lengths=None):
        self.spec = spec
        self.lang = lang
        self.other = OTHER[lang]
        self.sheet_name = {key: names[lang] for key, names in FIXED_SHEETS.items()}
        for sheet in spec.sheets:
            self.sheet_name[sheet.key] = label(sheet, lang)
        self.master = spec.sheets[0].key          # the sheet that holds the grid values
        columns = {spec.grid.key: (self.sheet_name[self.master], 0)}
        self.table_start = {}
        # An input table holds at least its template capacity, more for a long trace.
        self.table_capacity = {t.key: max(t.capacity, (table_lengths or {}).get(t.key, 0))
                               for t in spec.input_tables}
        for sheet in spec.sheets:
            for index, column in enumerate(sheet.columns, start=1):
                columns[column.key] = (self.sheet_name[sheet.key], index)
        for table in spec.input_tables:
            sheet = next(s for s in spec.sheets if s.key == table.sheet)
            self.table_start[table.key] = len(sheet.columns) + 2
        self.last_row = FIRST_ROW + grid_size - 1
        self.locator = Locator(spec, columns, FIRST_ROW, self.last_row)
        self.defined_names = {}   # name -> reference, filled by the sheet writers

    def tables_on(self, sheet_key):
        return [t for t in self.spec.input_tables if t.sheet == sheet_key]
