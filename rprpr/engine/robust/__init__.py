"""Robust verdicts: the audit under declared uncertainty (``uncertainty`` in the task).

On top of the three layers, beside the audit's own modules: the efforts as linear forms in
the links' inertial parameters (``regressor.py``), the consistency residual over the box
and the proven saturation window about each singular instant (``windows.py``), the
worst-case efforts over the box at given times (``worst.py``: export and sheet) and the
worst-case peak between the instants (``worst_peak.py``). docs/robust.md derives them.
"""
