"""The bounds layer: grid-free verdicts over the whole motion.

One branch and bound (``search.py``) over boxes of time with two sources, one motion
(``envelope.py``) and many plain pieces (``batch.py``): the certified torque peak, the
limit check and its windows, the closest approach; their records in ``verdicts.py``. It
imports the certified and exact layers.
"""
