"""The sheet's measures, in inches (and points where said): margins, gaps, lanes, columns."""

MARGIN = 0.15  # in, at the figure's edges
LEFT = 0.95  # in, from the figure's left edge to the axes: y tick labels and label
LANE = 2.85  # in, the lane right of the axes: legends and keys
LANE_GAP = 0.25  # in, between the axes and the lane
COLUMN = 2.45  # in, the width of one small multiple
COLUMN_GAP = 0.3  # in, between small multiples
UNIT_GAP = 0.85  # in, between small multiples when a row's columns differ in unit: y labels
SHARED_TIME = 0.5  # small multiples share one t axis when every t_f is at least this share
ROW_GAP = 0.22  # in, between the rows of one panel (sharing their t axis)
X_DECOR = 0.5  # in, tick labels and label under a panel's last row
TITLE_GAP = 0.16  # in, under a heading (half a tick label stands above the axes)
LEADING = 0.03  # in, between the lines of the title
PANEL_GAP = 0.3  # in, between panels
PAPER_MARGIN = 0.05  # in, at the top and bottom of a figure of a given size (its caption's)
PAPER_HEADING = 9.0  # pt, a sized figure's panel heading (one line: smaller if need be)
FONT_SCALE_TICK = 1.2  # a line of tick labels, in their size (ascent and descent)
DPI = 150  # the resolution text is measured at (the default of ``save``)
