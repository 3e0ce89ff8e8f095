"""Sites: conics (thesis §4.4, App. B canonical forms), circles and points, their exact rational
coefficients, the input reader (JSON schema), the point-to-site distance (§4.1 foot points) and a
common axis of symmetry of several sites."""
