"""The notebooks run headless in their small-sample mode, and are committed without outputs."""

import os
import re
import time
from pathlib import Path

import nbclient
import nbformat
import pytest

from tests.test_architecture import _bibliography_keys

NOTEBOOKS = Path(__file__).resolve().parents[1] / "notebooks"
EXPECTED = ("01_conventions_and_ggx", "02_fresnel_and_metals", "03_energy_conservation",
            "04_adobe_standard_material", "05_hazy_gloss", "06_speed_vs_accuracy",
            "07_openpbr", "08_explore", "09_conformance")
#: the switch every notebook reads
SMALL = "ADOBE_BSDF_NOTEBOOK_SMALL"


def _paths():
    return sorted(NOTEBOOKS.glob("*.ipynb"))


def test_every_notebook_is_there():
    assert [p.stem for p in _paths()] == list(EXPECTED)


@pytest.mark.parametrize("path", _paths(), ids=lambda p: p.stem)
def test_committed_without_outputs(path):
    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, (path.name, cell.source)
    assert nb.cells[0].cell_type == "markdown"
    cited = set(re.findall(r"\[([A-Z][A-Za-z'-]*\d{4}[a-z]?)[,\]]", nb.cells[0].source))
    assert cited and cited <= _bibliography_keys(), (path.name, cited)


@pytest.mark.parametrize("path", _paths(), ids=lambda p: p.stem)
def test_runs_in_small_mode(path, monkeypatch):
    """Executed in a kernel (nothing written back), small-sample mode."""
    monkeypatch.setenv(SMALL, "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(path, as_version=4)
    start = time.perf_counter()
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(NOTEBOOKS)}}).execute()
    assert time.perf_counter() - start < 300
    assert os.environ[SMALL] == "1"
