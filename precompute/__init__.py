"""Offline, exact stage (python-flint): generalised offsets of conics (thesis ch. 4, App. B),
polyhedral geometry and Canny--Emiris Newton matrices (§3.3.1, ch. 5), serialised to generated/."""
