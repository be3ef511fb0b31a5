"""Native charts: x–y scatter lines (over the grid or any column), per-item curves,
equal axes for profiles and polar diagrams, and column charts of spectra."""
import math
import weakref

import numpy as np

from xlsxwriter.utility import xl_range_abs, xl_rowcol_to_cell

from crankbook.spec.formulas import quote_sheet
from crankbook.spec.model import worded
from crankbook.writer import live_text
from crankbook.writer.layout import FIRST_ROW, label, unit_text

COLOURS = ["#1F77B4", "#D62728", "#2CA02C", "#FF7F0E", "#9467BD", "#8C564B", "#E377C2",
           "#7F7F7F", "#BCBD22", "#17BECF", "#393B79", "#AD494A", "#637939", "#8C6D31",
           "#843C39", "#7B4173"]
MUTED = "#A6A6A6"          # an emphasis below 2: a grey line behind the bold ones
GRIDLINES = {"visible": True, "line": {"color": "#D9D9D9"}}


def _ranges(layout, key, short=False, chart_spec=None, skip=0):
    """(name, range) of each curve of a series: one, or one per item (named by the item
    alone when ``short``: the curves of a polar diagram; "<curve> n" where the chart
    names its curves, and only its first ``curves`` items; by the item's value, "k = 3",
    where the axis is named by values: Layout.item_label)."""
    spec, locator = layout.spec, layout.locator
    quantity = spec.quantity.get(key) or spec.parameter[key]
    place = layout.places[key]
    if place.kind == "items":            # one value per item, down an items sheet
        cells = xl_range_abs(place.row, place.col, place.row + place.count - 1, place.col)
        return [(label(quantity, layout.lang), f"{quote_sheet(place.sheet)}!{cells}")]
    if not quantity.items:
        first = layout.locator.grid_rows[place.grid][0] + skip
        return [(label(quantity, layout.lang), locator.column_range(key, first=first))]
    count = place.count if chart_spec is None or chart_spec.curves is None else \
        min(place.count, chart_spec.curves)
    curve = chart_spec and (chart_spec.curve_zh if layout.lang == "zh" else chart_spec.curve_en)
    words = [worded(curve, i + 1) if curve else
             layout.item_label(quantity.items, layout.lang, i + 1, quantity.item_word)
             for i in range(count)]
    first = layout.locator.grid_rows[place.grid][0] + skip
    return [(words[i] if short or curve else f"{label(quantity, layout.lang)} — {words[i]}",
             locator.column_range(key, first=first, col=place.col + i)) for i in range(count)]


FRAME_INTERVALS = 6        # a frame spans about this many steps of a round size
# An equal-axis chart: its inner plot area is a square of the chart's pixels (title
# above, legend at the right), anchored inside one column wider than the chart, so
# no engine's column widths (font metrics) can stretch it.
CHART_SIZE = {"width": 760, "height": 430}
EQUAL_AXES_SIZE = {"width": 680, "height": 540}
PRINTED_SIZE = {"width": 700, "height": 450}       # the Charts sheet: two to a portrait page


def equal_axes_plot(size):
    """The inner plot area of an equal-axis chart of ``size``: a square of pixels."""
    side = 0.72 * size["height"]
    return {"x": 0.12, "y": 0.13, "width": side / size["width"], "height": side / size["height"]}
FRAME_LABEL = {"zh": "图框（两轴同比例，随数据变化）", "en": "chart frame (one scale on both axes, follows the data)"}


def nice_step(span):
    """The round step (1, 2, 5 × 10^k) at or above span/FRAME_INTERVALS: the same
    arithmetic as the frame's formula, so the cached value is the one engines compute."""
    if not span > 0:
        return 1.0
    raw = span / FRAME_INTERVALS
    power = 10.0 ** math.floor(math.log10(raw))
    ratio = raw / power
    return power * (1 if ratio <= 1 else 2 if ratio <= 2 else 5 if ratio <= 5 else 10)


class Frame:
    """The square frame of an equal-axis chart, the arithmetic of its live formulas
    operation for operation (so the cached values are the ones engines compute).

    Its ticks (``low``, ``high`` per axis, ``tick`` the common side) are multiples of
    one round ``step`` holding every point and the origin with a ``margin`` of an
    eighth of the data's ``span``; the narrower axis is padded by whole steps on both
    sides; the corners (``start``, ``end``) sit the margin inside the ticks.  Excel
    and LibreOffice widen an automatic axis by a step when the data comes within 5 %
    of its span of a tick; inset so, the frame makes both choose exactly its ticks,
    the same on x and y: one scale and no step of empty border.  The step is a whole
    multiple of the axes' major ``unit`` (fixed when the chart was built; by default
    the step itself)."""

    def __init__(self, xs, ys, unit=None):
        x = np.concatenate([np.ravel(v) for v in xs] + [np.zeros(1)])
        y = np.concatenate([np.ravel(v) for v in ys] + [np.zeros(1)])
        values = x[np.isfinite(x)], y[np.isfinite(y)]
        self.span = max(v.max() - v.min() for v in values)
        step = nice_step(self.span)
        if unit is not None:
            step = unit * max(1, -math.floor(-step / unit))
        self.step = step
        self.margin = frame_margin(self.span, step)
        self.low = [min(math.floor((v.min() - self.margin) / step) * step, -step)
                    for v in values]
        self.high = [max(-math.floor(-(v.max() + self.margin) / step) * step, step)
                     for v in values]
        self.tick = max(hi - lo for lo, hi in zip(self.low, self.high))
        self.start = [lo - math.floor((self.tick - (hi - lo)) / step / 2) * step + self.margin
                      for lo, hi in zip(self.low, self.high)]
        self.end = [s + self.tick - 2 * self.margin for s in self.start]


def frame_margin(span, step):
    """The frame's inset from its ticks: an eighth of the data's span (of the step
    while the span is 0).  Its ticks then span at most about twice the data (the
    rounding to steps), so the inset stays above the 5 % (of the corners' span) at
    which Excel and LibreOffice add a step of border."""
    return max(span, step) / 8


def frame_anchor(layout, sheet_spec):
    """(row, col) of the first frame block on a sheet: beside its charts."""
    name = layout.sheet_name[sheet_spec.key]
    last_col = max((p.col + p.count - 1 for p in layout.places.values() if p.sheet == name),
                   default=0)
    return FIRST_ROW, last_col + 3


def _frame_block(layout, sheet_spec, chart_spec):
    row, col = frame_anchor(layout, sheet_spec)
    index = [c for c in sheet_spec.charts if c.equal_axes].index(chart_spec)
    return row + 5 * index, col


NO_CURVE = {"zh": "（无）", "en": " (none)"}      # short: a long entry squeezes the plot
LEGEND_LABEL = {"zh": "图例名称（随数据变化）", "en": "legend names (follow the data)"}


def _names_block(layout, sheet_spec, chart_spec):
    """(row, col) of a live-names chart's caption, its curves' name cells below it:
    under the sheet's frames, one block per such chart (caption, a cell per curve, a
    gap).  The Charts sheet's copy of the chart finds the same cells."""
    row, col = frame_anchor(layout, sheet_spec)
    row += 5 * sum(1 for c in sheet_spec.charts if c.equal_axes)
    for other in sheet_spec.charts:
        if other is chart_spec:
            return row, col
        if live_legend(layout, other):
            row += 2 + sum(len(_ranges(layout, key, chart_spec=other)) for key in other.y)
    raise ValueError(f"chart of {sheet_spec.key!r} is not on its sheet")


def live_legend(layout, chart_spec):
    """Whether a chart's legend names are formulas in cells beside it: asked for
    (``live_names``), or a curve is an item whose name holds a result ("Main bearing
    {checked_journal}", crankbook.writer.live_text)."""
    if chart_spec.live_names:
        return True
    spec = layout.spec
    return any(spec.quantity[key].items and spec.axis[spec.quantity[key].items].live_keys
               for key in chart_spec.y if key in spec.quantity)


def _live_name(ws, layout, sheet, cell, name, values, y, none_when_blank):
    """A series name that is a formula in ``cell``: the curve's name (live where it
    holds a result), with NO_CURVE while its column holds no number when
    ``none_when_blank``; returns the series' name options (the cached text is the
    formula's result for ``y``)."""
    named = live_text.expression(name, layout)
    text = live_text.cached(name, layout)
    if none_when_blank:
        none = f"{named}&{live_text.quoted(NO_CURVE[layout.lang])}"
        formula = f"=IF(COUNT({values})=0,{none},{named})"
        text = text if np.isfinite(y).any() else text + NO_CURVE[layout.lang]
    else:
        formula = "=" + named
    if ws is not None:
        ws.write_formula(*cell, formula, None, text)
    return {"name": f"={quote_sheet(sheet)}!{xl_rowcol_to_cell(*cell, True, True)}",
            "name_data": [text]}


def write_frame(ws, layout, sheet_spec, chart_spec, x_ranges, y_ranges, frame, styles):
    """The live ``frame`` of an equal-axis chart, beside it on its sheet: its corners
    are formulas on the plotted ranges (``Frame``'s arithmetic), so the axes
    (automatic) follow every edit."""
    row, col = _frame_block(layout, sheet_spec, chart_spec)
    cell = lambda r, c: xl_rowcol_to_cell(r, c, True, True)
    span_cell, step_cell, tick_cell, margin_cell = (cell(row + 1, col + k) for k in (1, 2, 3, 4))
    lo = lambda ranges: f"MIN(0,{','.join(ranges)})"
    hi = lambda ranges: f"MAX(0,{','.join(ranges)})"
    ws.write(row, col, FRAME_LABEL[layout.lang], styles.subtitle)
    ws.write(row + 1, col, "D, s, T, m")
    ws.write_formula(row + 1, col + 1, f"=MAX({hi(x_ranges)}-{lo(x_ranges)},"
                                       f"{hi(y_ranges)}-{lo(y_ranges)})", None, frame.span)
    quarter = f"{span_cell}/{FRAME_INTERVALS}"
    power = f"10^INT(LOG10({quarter}))"
    nice = (f"IF({span_cell}<=0,1,{power}*IF({quarter}/{power}<=1,1,"
            f"IF({quarter}/{power}<=2,2,IF({quarter}/{power}<=5,5,10))))")
    # a whole multiple of the axes' major unit (fixed at the build's step): every
    # engine then rounds both axes to the same ticks and keeps them equal
    step = frame.step
    ws.write_formula(row + 1, col + 2, f"={step!r}*MAX(1,-INT(-{nice}/{step!r}))", None, step)
    ws.write_formula(row + 1, col + 4, f"=MAX({span_cell},{step_cell})/8", None, frame.margin)
    rows = []
    for axis, (name, ranges) in enumerate((("x", x_ranges), ("y", y_ranges))):
        r = row + 2 + axis
        ws.write(r, col, name)
        ws.write_formula(r, col + 3, f"=MIN(INT(({lo(ranges)}-{margin_cell})/{step_cell})"
                                     f"*{step_cell},-{step_cell})", None, frame.low[axis])
        ws.write_formula(r, col + 4, f"=MAX(-INT(-({hi(ranges)}+{margin_cell})/{step_cell})"
                                     f"*{step_cell},{step_cell})", None, frame.high[axis])
        # the frame's corners: its ticks padded by whole steps on both sides to the
        # common side, then the margin inside them
        ws.write_formula(r, col + 1, f"={cell(r, col + 3)}-INT(({tick_cell}-"
                                     f"({cell(r, col + 4)}-{cell(r, col + 3)}))/{step_cell}/2)"
                                     f"*{step_cell}+{margin_cell}", None, frame.start[axis])
        ws.write_formula(r, col + 2, f"={cell(r, col + 1)}+{tick_cell}-2*{margin_cell}", None,
                         frame.end[axis])
        rows.append(r)
    ws.write_formula(row + 1, col + 3,
                     "=MAX(" + ",".join(f"{cell(r, col + 4)}-{cell(r, col + 3)}" for r in rows)
                     + ")", None, frame.tick)


def _frame_series(layout, sheet_spec, chart_spec, frame):
    """The invisible two-point series of the ``frame``'s corners (with their cache)."""
    row, col = _frame_block(layout, sheet_spec, chart_spec)
    sheet = quote_sheet(layout.sheet_name[sheet_spec.key])
    return {"name": FRAME_LABEL[layout.lang],
            "categories": f"{sheet}!{xl_range_abs(row + 2, col + 1, row + 2, col + 2)}",
            "values": f"{sheet}!{xl_range_abs(row + 3, col + 1, row + 3, col + 2)}",
            "categories_data": [frame.start[0], frame.end[0]],
            "values_data": [frame.start[1], frame.end[1]],
            "line": {"none": True}, "marker": {"type": "none"}}


def chart_column_width(charts):
    """Width (characters) of a column that holds the widest of ``charts`` with margin."""
    widest = max(EQUAL_AXES_SIZE["width"] if c.equal_axes else CHART_SIZE["width"]
                 for c in charts)
    return math.ceil((widest + 30) / 7)


class Points(list):
    """A series' cached points, with their <c:numCache> XML made once (a chart and its
    copy on the Charts sheet share it)."""
    xml = None


def _skipped_rows(spec, sheet_spec, chart_spec):
    """The rows before the chart's ``rows_from`` value of its sheet's numeric grid."""
    if chart_spec.rows_from is None:
        return 0
    grid = spec.quantity[sheet_spec.grid]
    return max(0, int(round((chart_spec.rows_from - grid.start) / grid.step)))


def _from_row(values, skip):
    """A series' values from row ``skip`` on (the values themselves when 0)."""
    if not skip or not isinstance(values, np.ndarray) or values.ndim == 0:
        return values
    return values[skip:]


_POINTS = weakref.WeakKeyDictionary()    # numpy array -> {column: Points}


def _cache(values, column=None):
    """A series' cached points (blank where numpy gives NaN), one list per array."""
    array = np.asarray(values, dtype=float)
    try:
        made = _POINTS.setdefault(values, {}) if isinstance(values, np.ndarray) else {}
    except TypeError:
        made = {}
    if column not in made:
        data = array.ravel() if column is None else array[:, column]
        made[column] = Points(float(v) if math.isfinite(v) else None for v in data.tolist())
    return made[column]


def add_chart(book, chart_spec, sheet_spec, layout, results, ws=None, styles=None, size=None):
    """A chart of ``chart_spec`` (y series against x) for a sheet, every series with
    its cached points (a viewer that does not recalculate still draws it).  Given the
    sheet's worksheet ``ws``, an equal-axis chart also writes its live frame there."""
    spec, lang = layout.spec, layout.lang
    sheet = layout.sheet_name[sheet_spec.key]
    x_key = chart_spec.x or (chart_spec.x_each[0] if chart_spec.x_each else sheet_spec.grid)
    own_x = bool(chart_spec.x or chart_spec.x_each)      # not the sheet's grid
    x_q = spec.quantity.get(x_key) or spec.parameter[x_key]     # an items sheet's input too
    kind = "column" if chart_spec.type == "column" else "scatter"
    skip = _skipped_rows(spec, sheet_spec, chart_spec)
    chart = book.add_chart({"type": kind} if kind == "column" else
                           {"type": "scatter", "subtype": "straight"})
    x_ranges = _ranges(layout, x_key, skip=skip) if own_x else \
        [(None, f"{quote_sheet(sheet)}!$A${FIRST_ROW + 1 + skip}:"
                f"$A${layout.last_row(sheet_spec.grid) + 1}")]
    curves, xs, ys, used_x, used_y = 0, [], [], [], []
    unnamed = []                       # curves the legend leaves out (emphasis below 2)
    live = live_legend(layout, chart_spec)
    if live:
        names_row, names_col = _names_block(layout, sheet_spec, chart_spec)
        if ws is not None:
            ws.write(names_row, names_col, LEGEND_LABEL[lang], styles.subtitle)
    for number, key in enumerate(chart_spec.y):
        if chart_spec.x_each:             # each curve its own x (a cam's two profiles)
            x_key = chart_spec.x_each[number]
            x_ranges = _ranges(layout, x_key, skip=skip)
        for index, (name, values) in enumerate(_ranges(layout, key,
                                                        short=own_x,
                                                        chart_spec=chart_spec,
                                                        skip=skip)):
            x_range = x_ranges[index][1] if len(x_ranges) > 1 else x_ranges[0][1]
            y_source = _from_row(results[key], skip)
            y = np.asarray(y_source, dtype=float)
            y_column = None if y.ndim == 1 else index
            y = y if y_column is None else y[:, index]
            x_source = _from_row(results.get(x_key, []), skip)
            x = np.asarray(x_source, dtype=float)
            x_column = None if x.ndim == 1 else index
            x = x if x_column is None else x[:, index]
            series = {"name": name, "categories": x_range, "values": values,
                      "values_data": _cache(y_source, y_column)}
            if live:
                series.update(_live_name(ws, layout, sheet, (names_row + 1 + curves, names_col),
                                         name, values, y, chart_spec.live_names))
            if x.size == y.size:
                series["categories_data"] = _cache(x_source, x_column)
            colour = COLOURS[curves % len(COLOURS)]
            if kind == "column":
                series["fill"] = {"color": colour}
                series["gap"] = 50
            else:
                series["line"] = {"color": colour, "width": 1.5}
                series["marker"] = {"type": "none"}
                if key in chart_spec.heavy:
                    series["line"] = {"color": colour, "width": 3.0, "dash_type": "dash"}
                elif chart_spec.emphasis and number == 0:
                    level = float(np.ravel(results[chart_spec.emphasis])[index])
                    if level >= 2:           # the bold ones take the palette in turn
                        bold = COLOURS[(curves - len(unnamed)) % len(COLOURS)]
                        series["line"] = {"color": bold, "width": 2.5}
                    else:
                        series["line"] = {"color": MUTED, "width": 0.75,
                                          **({} if level >= 1 else {"dash_type": "dash"})}
                        unnamed.append(curves)
            chart.add_series(series)
            xs.append(x)
            ys.append(y)
            used_x.append(x_range)
            used_y.append(values)
            curves += 1
    chart.set_title({"name": label(chart_spec, lang, "title_"),
                     "name_font": {"size": 11, "bold": True}, "overlay": False})
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
    if chart_spec.log == "y":
        y_axis["log_base"] = 10
        y_axis["crossing"] = "min"           # the x axis at the bottom, not at 1 MPa
    elif chart_spec.log:
        x_axis["log_base"] = y_axis["log_base"] = 10
        x_axis["crossing"] = "min"
    size = dict(size or (EQUAL_AXES_SIZE if chart_spec.equal_axes else CHART_SIZE))
    legend = {"position": "bottom"} if curves > 1 else {"none": True}
    if unnamed:
        legend = {"position": "right", "delete_series": unnamed}
    if chart_spec.equal_axes:
        frame = Frame(xs, ys)
        if ws is not None:
            write_frame(ws, layout, sheet_spec, chart_spec, used_x, used_y, frame, styles)
        chart.add_series(_frame_series(layout, sheet_spec, chart_spec, frame))
        # automatic bounds over the frame, one major unit on both (the build's frame
        # step); the axes cross at the origin, their labels at the edge
        # thousands as "k": labels stay short enough to stand upright
        numbers = {"num_font": {"size": 8}, "major_unit": frame.step, "crossing": 0}
        if frame.step >= 1000:
            numbers["num_format"] = '0,"k"'
        x_axis.update(numbers)
        y_axis.update(numbers, label_position="low")
        chart.set_plotarea({"layout": equal_axes_plot(size), "border": {"color": "#595959"}})
        legend = {"position": "right", "delete_series": [curves]} if curves > 1 else \
            {"none": True}
    chart.set_x_axis(x_axis)
    chart.set_y_axis(y_axis)
    chart.set_legend(legend)
    chart.show_hidden_data()              # rows folded for printing are still plotted
    chart.set_size(size)
    return chart


CHART_ROW_PT = 15.75      # explicit row height: a chart's rows cannot change size
CHARTS_PER_PAGE = 2


def write_charts_sheet(book, layout, results, styles):
    """Every chart of the workbook again on one sheet, two to a printed portrait page,
    filling it (the series sheets print their tables).  Each chart sits inside one
    column wider than it, on rows of a set height, so it prints at its own size
    whatever the fonts of the machine."""
    from crankbook.writer.print_setup import A4
    spec, lang = layout.spec, layout.lang
    charts = [(sheet, chart) for sheet in spec.sheets for chart in sheet.charts]
    if not charts:
        return
    ws = book.add_worksheet(layout.sheet_name["charts"])
    ws.write(0, 0, "图表 / Charts" if lang == "zh" else "Charts / 图表", styles.title)
    ws.set_column(0, 0, math.ceil((PRINTED_SIZE["width"] + 12) / 7))
    row_px = CHART_ROW_PT * 4 / 3
    chart_rows = math.ceil(PRINTED_SIZE["height"] / row_px)
    per_chart = chart_rows + 2                       # a caption row and a gap
    row, breaks = 1, []
    for index, (sheet, chart_spec) in enumerate(charts):
        if index and index % CHARTS_PER_PAGE == 0:
            breaks.append(row)
        chart = add_chart(book, chart_spec, sheet, layout, results, size=PRINTED_SIZE)
        ws.write(row, 0, label(sheet, lang), styles.subtitle)
        ws.insert_chart(row + 1, 0, chart, {"x_offset": 6, "y_offset": 2,
                                            "object_position": 3})
        row += per_chart
    for r in range(row + 1):
        ws.set_row(r, CHART_ROW_PT)
    ws.set_h_pagebreaks(breaks)
    ws.set_paper(A4)
    ws.set_portrait()
    ws.set_margins(left=0.4, right=0.4, top=0.5, bottom=0.5)
    ws.fit_to_pages(1, 0)
    ws.print_area(0, 0, row, 0)
