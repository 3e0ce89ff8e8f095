"""Polynomial algebra of the locator: numeric polynomials and offsets of conic families
(thesis §4.4, §5.3), towers of quadratic extensions (§3.1.2–§3.1.3), algebraic offsets of plane
curves and the degree formula of Theorem 4.2.18."""
