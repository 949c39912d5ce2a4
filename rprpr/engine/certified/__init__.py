"""The certified layer: floats with proofs (ball arithmetic, rounded outward).

Balls and jets of balls, the efforts stacked over boxes, the forms near a singular instant
(zones) and near E at A or B (through), certified values at any float time (motion) and on
a grid (sampling). It imports only the exact layer.
"""
