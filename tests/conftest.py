"""Test-session settings: one BLAS thread (OpenBLAS with 2 threads was 14x slower on a dense
eig on the 2-core CI machines), and a fixed hypothesis profile so CI time is predictable."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings
from threadpoolctl import threadpool_limits

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
_limits = threadpool_limits(limits=1)

settings.register_profile("ci", deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
settings.load_profile("ci")


def _sample_seed() -> int:
    """Seed of the sampled slow reference runs: CURVEDVORONOI_TEST_SEED if set, else the CI run's
    id, else today's date (YYYYMMDD), so that the sample changes between submissions and every
    run can be reproduced from the seed printed in the log."""
    for var in ("CURVEDVORONOI_TEST_SEED", "GITHUB_RUN_ID", "CI_PIPELINE_ID", "BUILD_NUMBER"):
        v = os.environ.get(var, "").strip()
        if v.isdigit():
            return int(v) % (2 ** 31)
    import datetime

    return int(datetime.date.today().strftime("%Y%m%d"))


os.environ["CURVEDVORONOI_TEST_SEED"] = str(_sample_seed())


def pytest_report_header(config):
    return f"sampled reference runs: CURVEDVORONOI_TEST_SEED={os.environ['CURVEDVORONOI_TEST_SEED']}"


def pytest_terminal_summary(terminalreporter):
    terminalreporter.write_line("sampled reference runs used CURVEDVORONOI_TEST_SEED="
                                f"{os.environ['CURVEDVORONOI_TEST_SEED']} (set it to reproduce)")


@pytest.fixture(scope="session")
def cgal_peer_program():
    """The compiled CGAL Apollonius_graph_2 peer (tests/cgal/).  Without g++ or libcgal-dev the
    comparison is skipped with the install line; under CI (which installs both) it fails instead."""
    sys.path.insert(0, str(Path(__file__).with_name("cgal")))
    import cgal_peer

    try:
        return cgal_peer.build()
    except cgal_peer.PeerMissing as exc:
        if os.environ.get("CI"):
            pytest.fail(f"CGAL peer unavailable in CI: {exc}")
        pytest.skip(f"comparison with CGAL Apollonius_graph_2 not run on this machine: {exc} "
                    "(sudo apt-get install libcgal-dev g++; CI installs both and fails instead of skipping)")


@pytest.fixture(autouse=True)
def _mpmath_digits(request):
    """The digits a module's mpmath references need (``pytestmark = pytest.mark.mpmath_dps(n)``),
    set for each test and restored after it: a module-level ``mpmath.mp.dps = n`` leaks into other
    modules and is undone by their settings."""
    marker = request.node.get_closest_marker("mpmath_dps")
    if marker is None:
        yield
        return
    import mpmath

    with mpmath.workdps(marker.args[0]):
        yield
