"""Importing the packages changes no process-wide setting: numba's threading layer stays the
user's (or numba's default) until an application asks for the workqueue layer."""

import json
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.api


def _layers(code, **env):
    environ = {k: v for k, v in os.environ.items() if k != "NUMBA_THREADING_LAYER"} | env
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environ, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_import_leaves_the_threading_layer_alone():
    code = ("import json, numba; before = numba.config.THREADING_LAYER\n"
            "import bubbleoptics, bubbleoptics.filmflow, tracer\n"
            "print(json.dumps([before, numba.config.THREADING_LAYER]))")
    before, after = _layers(code)
    assert after == before == "default"


def test_prefer_workqueue_threads_respects_the_users_choice():
    code = ("import json, numba\nfrom bubbleoptics.resources import prefer_workqueue_threads\n"
            "print(json.dumps([prefer_workqueue_threads(), numba.config.THREADING_LAYER]))")
    assert _layers(code) == ["workqueue", "workqueue"]
    assert _layers(code, NUMBA_THREADING_LAYER="omp") == ["omp", "omp"]
