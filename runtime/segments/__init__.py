"""The Voronoi diagram of points and segments (thesis §2.2: semi-algebraic sites decomposed into
harmless sites), its certificate and the medial axis of polygons (thesis §2.3)."""
