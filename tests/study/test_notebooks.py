"""Execute every ``notebooks/*.ipynb`` end to end in quick mode; any cell error (including the
cells' own sanity ``assert``s) fails the test.

The notebooks run in the ``python3`` kernel, i.e. ipykernel in this interpreter, with
``BUBBLEOPTICS_QUICK=1`` (coarser grids) and the Agg matplotlib backend (no display needed).
New notebooks are picked up automatically.
"""

from __future__ import annotations

import pathlib
import shutil
import sys

import pytest

NOTEBOOKS_DIR = pathlib.Path(__file__).resolve().parents[2] / "notebooks"
NOTEBOOKS = sorted(NOTEBOOKS_DIR.glob("*.ipynb"))
KERNEL_NAME = "python3"


def _check_kernel():
    """The python3 kernel must exist and run this interpreter (where bubbleoptics is installed)."""
    from jupyter_client.kernelspec import KernelSpecManager, NoSuchKernel

    try:
        spec = KernelSpecManager().get_kernel_spec(KERNEL_NAME)
    except NoSuchKernel:
        pytest.fail(f"no {KERNEL_NAME!r} kernel spec: install ipykernel in {sys.prefix}")
    exe = spec.argv[0]
    # jupyter_client runs a bare "python"/"python3"/"python3.X" as sys.executable
    bare = {"python", f"python{sys.version_info[0]}", "python{}.{}".format(*sys.version_info[:2])}
    if exe not in bare:
        found = shutil.which(exe) or exe
        if pathlib.Path(found).absolute() != pathlib.Path(sys.executable).absolute():
            pytest.fail(
                f"the {KERNEL_NAME!r} kernel runs {exe!r}, not this interpreter {sys.executable!r}; "
                f"the notebook could not import this checkout of bubbleoptics"
            )


def test_notebooks_found():
    assert NOTEBOOKS, f"no notebooks in {NOTEBOOKS_DIR}"


@pytest.mark.notebook
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, monkeypatch):
    import nbclient
    import nbformat

    _check_kernel()
    monkeypatch.setenv("BUBBLEOPTICS_QUICK", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name=KERNEL_NAME, resources={"metadata": {"path": str(NOTEBOOKS_DIR)}}
    )
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as exc:
        pytest.fail(f"{path.name}: a cell failed\n{exc}")
    errors = [
        out for cell in nb.cells if cell.cell_type == "code" for out in cell.get("outputs", [])
        if out.get("output_type") == "error"
    ]
    assert not errors, errors
    assert all(cell.get("execution_count") for cell in nb.cells if cell.cell_type == "code"), "a cell did not run"
