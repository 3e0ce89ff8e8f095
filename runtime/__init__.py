"""Online stage: load generated artefacts and answer conflict-locator queries with certificates.

Public API (imported lazily so that ``python -m curvedvoronoi --help`` stays fast):

* :class:`runtime.result.LocatorResult`, :class:`runtime.result.VoronoiVertex`
* :func:`runtime.artefacts.load_offset` -- verified loading of offset artefacts
"""
from .result import LocatorResult, VoronoiVertex, LocatorError, InvalidConicError  # noqa: F401
