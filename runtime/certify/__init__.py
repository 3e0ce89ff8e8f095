"""Proofs about numeric solutions (thesis §3.3.3, §5.2, ch. 6): rigorous foot-point distances,
Krawczyk existence-and-uniqueness tests, charts for far solutions, completeness of a solution
list, and the certification of a locator answer."""
