"""The independent certificate of a Voronoi diagram of curved sites (thesis §1.2): vertices
(:mod:`.vertices`, :mod:`.conic_vertices`), edges (:mod:`.edges`, :mod:`.curved`, :mod:`.strips`,
:mod:`.tail`, :mod:`.edge_checks`), rigorous site data (:mod:`.site_table`, :mod:`.support`) and
the closure and accounting of the graph (:mod:`.closure`); :func:`verify` in :mod:`.certificate`
puts them together.  It reads the reported combinatorics only and never calls the construction."""
from .certificate import verify

__all__ = ["verify"]
