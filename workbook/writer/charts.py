"""Native scatter charts: one per quantity sheet, crank angle on the x axis."""
from workbook.writer.layout import label, unit_text

COLOURS = ["#1F77B4", "#D62728", "#2CA02C", "#FF7F0E", "#9467BD", "#8C564B"]


def add_quantity_chart(book, sheet_spec, layout, x_range):
    """A scatter chart of the sheet's ``chart`` series against crank angle."""
    spec, lang = layout.spec, layout.lang
    chart = book.add_chart({"type": "scatter", "subtype": "straight"})
    for index, key in enumerate(sheet_spec.chart):
        quantity = spec.quantity[key]
        chart.add_series({
            "name": label(quantity, lang),
            "categories": x_range,
            "values": layout.locator.column_range(key),
            "line": {"color": COLOURS[index % len(COLOURS)], "width": 1.5},
            "marker": {"type": "none"},
        })
    unit = unit_text(sheet_spec.unit)
    chart.set_title({"name": label(sheet_spec, lang, "title_"),
                     "name_font": {"size": 11, "bold": True}})
    grid = spec.quantity[sheet_spec.grid]
    low, high, major = grid.axis
    chart.set_x_axis({"name": f"{label(grid, lang)} [{unit_text(grid.unit)}]", "min": low,
                      "max": high, "major_unit": major, "major_gridlines": {"visible": True,
                                                            "line": {"color": "#D9D9D9"}},
                      "label_position": "low"})
    chart.set_y_axis({"name": f"{label(sheet_spec, lang, 'axis_')} [{unit}]",
                      "major_gridlines": {"visible": True, "line": {"color": "#D9D9D9"}}})
    chart.set_legend({"position": "bottom"} if len(sheet_spec.chart) > 1 else {"none": True})
    chart.set_size({"width": 760, "height": 430})
    return chart
