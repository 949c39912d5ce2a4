"""The exact layer: the paper in rational arithmetic (python-flint ``fmpq``, number fields).

The trajectory as exact polynomials, power series, the paper's equations for any number
type behind the mechanism seam (``mechanism.py``), real roots, the Type II instants with
their orders, cases, principles and eq. (34), the jumps at knots. It imports no other
layer of the engine.
"""
