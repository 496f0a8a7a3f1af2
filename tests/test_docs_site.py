"""The documentation site builds with ``mkdocs build --strict`` and gives every public name
an API entry."""

import importlib
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the modules ``docs/reference.md`` documents
MODULES = ("adobe_bsdf", "adobe_bsdf.bsdf", "adobe_bsdf.composition", "adobe_bsdf.frame",
           "adobe_bsdf.fresnel", "adobe_bsdf.microfacet", "adobe_bsdf.lobes",
           "adobe_bsdf.materials", "adobe_bsdf.materials.spec", "adobe_bsdf.materials.asm",
           "adobe_bsdf.materials.openpbr", "adobe_bsdf.materials.openpbr.mapping",
           "adobe_bsdf.materials.openpbr.transport",
           "adobe_bsdf.materials.openpbr.draft",
           "adobe_bsdf.haze", "adobe_bsdf.hazy", "adobe_bsdf.dispersion", "adobe_bsdf.spectral",
           "adobe_bsdf.media", "adobe_bsdf.quadrature", "adobe_bsdf.tables", "adobe_bsdf.render",
           "adobe_bsdf.plot", "adobe_bsdf.validation", "adobe_bsdf.validation.cases",
           "adobe_bsdf.config", "adobe_bsdf.darkening", "adobe_bsdf.layered", "adobe_bsdf.phase",
           "adobe_bsdf.io",
           "adobe_bsdf.thin_film")


def test_site_builds_strictly_with_every_public_name(tmp_path):
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-d",
                           str(tmp_path / "site")], cwd=ROOT, capture_output=True, text=True,
                          env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    html = (tmp_path / "site" / "reference" / "index.html").read_text(encoding="utf-8")
    ids = set(re.findall(r'id="(adobe_bsdf[\w.]*)"', html))
    missing = [f"{m}.{n}" for m in MODULES for n in importlib.import_module(m).__all__
               if f"{m}.{n}" not in ids and f"{m}.{n}.{n}" not in ids]
    assert not missing, missing
    assert (tmp_path / "site" / "figures" / "gallery.png").exists()
