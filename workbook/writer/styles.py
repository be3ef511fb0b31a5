"""Cell formats shared by every sheet writer."""
import re

from crankbook.spec import units

FONT = "Arial"          # Arial falls back to a CJK font for Chinese in Excel and LibreOffice


BILINGUAL = re.compile(r'"([^"|]*)\|([^"|]*)"')


def in_language(fmt, lang):
    """A number format whose quoted words hold both languages, "中文|English", with the
    build's language only (a text shown by a number format cannot spill into the next
    cell: it must fit its column)."""
    return BILINGUAL.sub(lambda m: f'"{m.group(1) if lang == "zh" else m.group(2)}"', fmt)


class Styles:
    """Creates each xlsxwriter format once per workbook."""

    def __init__(self, book, lang="zh"):
        self._book = book
        self.lang = lang
        self._cache = {}
        # top: a cell beside wrapped text in a tall row stands on its first line
        base = {"font_name": FONT, "font_size": 10, "valign": "top"}
        self.base = base
        # taller than its row: at the bottom, it rises into the empty row above
        self.title = self._make(bold=True, font_size=14, valign="bottom")
        self.subtitle = self._make(italic=True, font_color="#555555")
        self.warning = self._make(bold=True, font_color="#C00000")
        self.title_wrap = self._make(bold=True, font_size=14, text_wrap=True, valign="top")
        self.subtitle_wrap = self._make(italic=True, font_color="#555555", text_wrap=True,
                                        valign="top")
        self.header = self._make(bold=True, text_wrap=True, valign="top", bg_color="#DDE6F0",
                                 border=1)
        self.header_other = self._make(text_wrap=True, valign="top", bg_color="#EEF2F7",
                                       border=1, font_color="#333333")
        self.unit = self._make(italic=True, align="center", bg_color="#EEF2F7", border=1)
        self.group = self._make(bold=True, bg_color="#F2F2F2")
        self.text = self._make(text_wrap=True, valign="top")
        self.key = self._make(font_name="Consolas", font_color="#1F3864")
        # cells beside wrapped text in a tall row: at its top, like the text
        self.top = self._make(valign="top")
        self.key_top = self._make(font_name="Consolas", font_color="#1F3864", valign="top")
        self.status = self._make(bold=True, text_wrap=True, border=2, valign="vcenter")
        self.status_ok = book.add_format({"bg_color": "#E2EFDA", "font_color": "#375623"})
        self.status_bad = book.add_format({"bg_color": "#FFC7CE", "font_color": "#9C0006"})

    def _make(self, **props):
        return self._book.add_format({**self.base, **props})

    def number(self, unit, fmt=None, role="output"):
        """Format of a number cell: ``role`` 'input' (yellow, editable) or 'output'."""
        fmt = in_language(fmt or units.number_format(unit), self.lang)
        key = (fmt, role)
        if key not in self._cache:
            props = {"num_format": fmt}
            if role == "input":
                props.update(bg_color="#FFF2CC", font_color="#0000CC", border=1,
                             border_color="#BF9000", locked=False)
            self._cache[key] = self._make(**props)
        return self._cache[key]
