"""The Voronoi diagram of many curved sites (thesis §1.2): geometry, construction, verification, output."""
