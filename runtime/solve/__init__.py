"""Solvers of the triple offset system o1 = o2 = o3 = 0 (thesis §5.3–§5.5): Macaulay null space
and multiplication maps, homotopy continuation, and the exact rational route (msolve)."""
