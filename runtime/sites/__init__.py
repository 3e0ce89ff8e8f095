"""Sites: conics (thesis §4.4, App. B canonical forms), circles and points, their exact rational
coefficients, the input reader (JSON schema) and the point-to-site distance (§4.1 foot points)."""
