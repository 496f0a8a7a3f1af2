"""The package reads as its architecture: the import layers hold (import-linter), generic
lobes carry no material recipe, and every citation resolves in the bibliography."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = shutil.which("lint-imports") or str(Path(sys.executable).with_name("lint-imports"))
#: trees whose text is the product (what a reader sees)
PRODUCT = [ROOT / "adobe_bsdf", ROOT / "docs", ROOT / "notebooks", ROOT / "README.md"]
TEXT_SUFFIXES = {".py", ".md", ".ipynb"}


def _lint(cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([LINT, "--config", str(ROOT / "pyproject.toml"), "--no-cache"],
                          cwd=cwd, capture_output=True, text=True, timeout=300,
                          env={"PYTHONPATH": str(cwd), "PATH": str(Path(LINT).parent)})


def test_import_layers_hold():
    result = _lint(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 kept, 0 broken" in result.stdout


def test_upward_import_breaks_the_layers(tmp_path):
    """The contract is not vacuous: a lobe that imports a material fails it."""
    shutil.copytree(ROOT / "adobe_bsdf", tmp_path / "adobe_bsdf",
                    ignore=shutil.ignore_patterns("__pycache__"))
    lambert = tmp_path / "adobe_bsdf" / "lobes" / "lambert.py"
    lambert.write_text(lambert.read_text() + "\nfrom adobe_bsdf import materials  # noqa\n")
    result = _lint(tmp_path)
    assert result.returncode != 0
    assert "adobe_bsdf.lobes is not allowed to import adobe_bsdf.materials" in result.stdout


def _files(*roots: Path):
    for root in roots:
        paths = [root] if root.is_file() else sorted(root.rglob("*"))
        for path in paths:
            if path.suffix in TEXT_SUFFIXES and "__pycache__" not in path.parts:
                yield path


def test_generic_lobes_hold_no_material_recipe():
    """``lobes/`` and the microfacet maths name the ASM (or OpenPBR) only in citations."""
    found = []
    for path in _files(ROOT / "adobe_bsdf" / "lobes", ROOT / "adobe_bsdf" / "microfacet.py"):
        for number, line in enumerate(path.read_text().splitlines(), 1):
            text = re.sub(r"\[[A-Za-z]+\d{4}[^\]]*\]", "", line)  # citations are fine
            if re.search(r"asm|openpbr", text, re.IGNORECASE):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "\n".join(found)


def test_no_reference_outside_the_repository():
    """No source document is named by a private file name or a path outside the tree."""
    pattern = re.compile(r"seed[s]? ?`*0\d\d|seeds/|shared/", re.IGNORECASE)
    found = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
             for path in _files(*PRODUCT)
             for n, line in enumerate(path.read_text().splitlines(), 1) if pattern.search(line)]
    assert not found, "\n".join(found)


def _bibliography_keys() -> set[str]:
    text = (ROOT / "docs" / "references.md").read_text()
    return set(re.findall(r"^- \*\*\[([A-Za-z][A-Za-z'-]*\d{4}[a-z]*)\]\*\*", text, re.M))


def test_bibliography_is_readable():
    keys = _bibliography_keys()
    assert {"Kutz2021", "Hoffman2023", "Barla2018", "Andersson2023", "OpenPBR2026"} <= keys


@pytest.mark.parametrize("path", list(_files(*PRODUCT)), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_citation_resolves(path):
    keys = _bibliography_keys()
    cited = set(re.findall(r"\[([A-Z][A-Za-z'-]*\d{4}[a-z]*)[,\]]", path.read_text()))
    missing = sorted(cited - keys)
    assert not missing, f"{path.relative_to(ROOT)} cites {missing}, not in docs/references.md"


def test_every_subpackage_is_installed():
    """pyproject's explicit package list names every package folder (a wheel holds only
    those; an editable install would hide a missing one)."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
                 ["packages"])
    found = {".".join(p.parent.relative_to(ROOT).parts)
             for p in (ROOT / "adobe_bsdf").rglob("__init__.py")}
    assert found <= listed, sorted(found - listed)
