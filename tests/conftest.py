"""Shared pytest configuration for the bubbleoptics test-suite.

Hypothesis profiles
-------------------
``ci`` (the default) keeps the property tests deterministic and affordable on a slow
machine: a fixed number of examples, ``derandomize=True`` (the examples are a function of
the test alone, so every CI run sees the same inputs and a failure always reproduces), no
per-example deadline (the first call of a numba kernel may load its cache) and no example
database on disk.

``thorough`` is for occasional local runs hunting for counterexamples: ten times as many
examples, randomised, with the database so that a failure found once is replayed first.

Choose with ``HYPOTHESIS_PROFILE=thorough pytest tests/bubbleoptics/test_properties.py`` (or pytest's own
``--hypothesis-profile thorough`` option).
"""

import os

from hypothesis import HealthCheck, settings

from bubbleoptics.resources import prefer_workqueue_threads

prefer_workqueue_threads()  # as the tracer command does (import bubbleoptics changes no setting)
# One integrator with every feature serves every test scene (compiled once, not once per feature set;
# tests/tracer/test_features.py checks that the specialised kernels give the same images).
os.environ.setdefault("TRACER_FEATURES", "all")
# No second compiling process beside a first render (tracer.rendering.compile_helper): the two
# test workers already use both cores; tests/tracer/test_compile_helper.py turns it on where it tests it.
os.environ.setdefault("TRACER_COMPILE_HELPER", "0")

settings.register_profile(
    "ci",
    max_examples=200,
    deadline=None,
    derandomize=True,
    database=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "thorough",
    max_examples=2000,
    deadline=None,
    derandomize=False,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import pytest  # noqa: E402


@pytest.fixture(scope="session")
def client():
    """A Dask LocalCluster of two one-thread workers (tracer.rendering.dask.local_cluster), shared by
    the tests of one pytest process (test_movie.py, test_cluster.py)."""
    distributed = pytest.importorskip("distributed")
    from tracer.rendering.dask import local_cluster

    with local_cluster(2) as cluster, distributed.Client(cluster) as c:
        yield c


@pytest.fixture()
def editor(browser, server):
    """The scene editor open in a page of the browser test module's ``browser``, served by its
    ``server`` (tests/tracer/test_editor_browser.py, tests/tracer/test_editor_attacks.py); closed after."""
    from tracer.editor.testing import EditorPage

    ed = EditorPage(browser, server)
    yield ed
    ed.page.close()
