"""Native charts: x–y scatter lines (over the grid or any column), per-item curves,
equal axes for profiles and polar diagrams, and column charts of spectra."""
import math

import numpy as np

from xlsxwriter.utility import xl_range_abs

from crankbook.formulas import quote_sheet
from crankbook.writer.layout import FIRST_ROW, label, unit_text

COLOURS = ["#1F77B4", "#D62728", "#2CA02C", "#FF7F0E", "#9467BD", "#8C564B", "#E377C2",
           "#7F7F7F", "#BCBD22", "#17BECF", "#393B79", "#AD494A", "#637939", "#8C6D31",
           "#843C39", "#7B4173"]
GRIDLINES = {"visible": True, "line": {"color": "#D9D9D9"}}


def _ranges(layout, key, results, short=False):
    """(name, range) of each curve of a series: one, or one per item (named by the item
    alone when ``short``: the curves of a polar diagram)."""
    spec, locator = layout.spec, layout.locator
    quantity = spec.quantity.get(key) or spec.parameter[key]
    place = layout.places[key]
    if place.kind == "items":            # one value per item, down an items sheet
        cells = xl_range_abs(place.row, place.col, place.row + place.count - 1, place.col)
        return [(label(quantity, layout.lang), f"{quote_sheet(place.sheet)}!{cells}")]
    if not quantity.items:
        return [(label(quantity, layout.lang), locator.column_range(key))]
    words = [layout.item_label(quantity.items, layout.lang, i + 1) for i in range(place.count)]
    return [(words[i] if short else f"{label(quantity, layout.lang)} — {words[i]}",
             locator.column_range(key, col=place.col + i)) for i in range(place.count)]


def _nice(value):
    """A round number ≥ value (1, 2, 2.5 or 5 × 10^k)."""
    if value <= 0 or not math.isfinite(value):
        return 1.0
    power = 10 ** math.floor(math.log10(value))
    for step in (1, 2, 2.5, 5, 10):
        if step * power >= value:
            return step * power
    return 10 * power


def _equal_bounds(xs, ys):
    """Axis limits with one scale on both axes (a circle stays a circle)."""
    x = np.concatenate([np.ravel(v) for v in xs]) if xs else np.zeros(1)
    y = np.concatenate([np.ravel(v) for v in ys]) if ys else np.zeros(1)
    x, y = x[np.isfinite(x)], y[np.isfinite(y)]
    if not x.size or not y.size:
        return None
    half = _nice(max(np.ptp(x), np.ptp(y), 1e-12) / 2 * 1.1)
    centre = [(np.max(v) + np.min(v)) / 2 for v in (x, y)]
    step = half / 2
    return [(math.floor((c - half) / step) * step, math.floor((c - half) / step) * step + 2 * half)
            for c in centre]


def add_chart(book, chart_spec, sheet_spec, layout, results):
    """A chart of ``chart_spec`` (y series against x) for a sheet."""
    spec, lang = layout.spec, layout.lang
    sheet = layout.sheet_name[sheet_spec.key]
    x_key = chart_spec.x or sheet_spec.grid
    x_q = spec.quantity.get(x_key) or spec.parameter[x_key]     # an items sheet's input too
    kind = "column" if chart_spec.type == "column" else "scatter"
    chart = book.add_chart({"type": kind} if kind == "column" else
                           {"type": "scatter", "subtype": "straight"})
    x_ranges = _ranges(layout, x_key, results) if chart_spec.x else \
        [(None, f"{quote_sheet(sheet)}!$A${FIRST_ROW + 1}:$A${layout.last_row(sheet_spec.grid) + 1}")]
    curves, xs, ys = 0, [], []
    for number, key in enumerate(chart_spec.y):
        if chart_spec.x_each:             # each curve its own x (a cam's two profiles)
            x_key = chart_spec.x_each[number]
            x_ranges = _ranges(layout, x_key, results)
        for index, (name, values) in enumerate(_ranges(layout, key, results,
                                                        short=bool(chart_spec.x))):
            x_range = x_ranges[index][1] if len(x_ranges) > 1 else x_ranges[0][1]
            series = {"name": name, "categories": x_range, "values": values}
            colour = COLOURS[curves % len(COLOURS)]
            if kind == "column":
                series["fill"] = {"color": colour}
                series["gap"] = 50
            else:
                series["line"] = {"color": colour, "width": 1.5}
                series["marker"] = {"type": "none"}
            chart.add_series(series)
            y = np.asarray(results[key], dtype=float)
            ys.append(y if y.ndim == 1 else y[:, index])
            x = np.asarray(results.get(x_key, []), dtype=float)
            xs.append(x if x.ndim == 1 else x[:, index])
            curves += 1
    chart.set_title({"name": label(chart_spec, lang, "title_"),
                     "name_font": {"size": 11, "bold": True}})
    x_name = label(chart_spec, lang, "x_axis_") or label(x_q, lang)
    x_unit = unit_text(chart_spec.x_unit or x_q.unit)
    x_axis = {"name": f"{x_name} [{x_unit}]", "major_gridlines": GRIDLINES,
              "label_position": "low"}
    y_axis = {"name": f"{label(chart_spec, lang, 'axis_')} [{unit_text(chart_spec.unit)}]",
              "major_gridlines": GRIDLINES}
    if chart_spec.x is None and getattr(x_q, "chart_range", None) and x_q.chart_range[0] is not None \
            and kind == "scatter":
        low, high, major = x_q.chart_range
        x_axis.update({"min": low, "max": high, "major_unit": major})
    if chart_spec.log:
        x_axis["log_base"] = y_axis["log_base"] = 10
        x_axis["crossing"] = "min"
    size = {"width": 760, "height": 430}
    if chart_spec.equal_axes:
        bounds = _equal_bounds(xs, ys)
        if bounds:
            (x0, x1), (y0, y1) = bounds
            x_axis.update({"min": x0, "max": x1, "major_unit": (x1 - x0) / 4})
            y_axis.update({"min": y0, "max": y1, "major_unit": (y1 - y0) / 4})
            x_axis["crossing"] = y0
            y_axis["crossing"] = x0
        chart.set_plotarea({"layout": {"x": 0.16, "y": 0.12, "width": 0.72, "height": 0.72}})
        size = {"width": 560, "height": 560}
    chart.set_x_axis(x_axis)
    chart.set_y_axis(y_axis)
    chart.set_legend({"position": "bottom"} if curves > 1 else {"none": True})
    chart.show_hidden_data()              # rows folded for printing are still plotted
    chart.set_size(size)
    return chart


def write_charts_sheet(book, layout, results, styles):
    """Every chart of the workbook again on one sheet, two to a printed page: what
    the series sheets print is their tables."""
    from crankbook.writer.print_setup import A4
    spec, lang = layout.spec, layout.lang
    charts = [(sheet, chart) for sheet in spec.sheets for chart in sheet.charts]
    if not charts:
        return
    ws = book.add_worksheet(layout.sheet_name["charts"])
    ws.write(0, 0, "图表 / Charts" if lang == "zh" else "Charts / 图表", styles.title)
    ws.set_column(0, 25, 8.43)
    band, breaks = 2, []
    for index, (sheet, chart_spec) in enumerate(charts):
        chart = add_chart(book, chart_spec, sheet, layout, results)
        chart.set_size({"width": 560, "height": 540})
        column = 0 if index % 2 == 0 else 9
        ws.write(band - 1, column, label(sheet, lang), styles.subtitle)
        ws.insert_chart(band, column, chart)
        if index % 2 == 1 or index == len(charts) - 1:
            band += 30
            breaks.append(band - 1)       # two charts a page
    ws.set_h_pagebreaks(breaks[:-1])
    ws.set_paper(A4)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    ws.print_area(0, 0, band, 17)
