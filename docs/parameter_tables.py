"""Write every material's parameter table into its docs page (run from the repository root).

    python docs/parameter_tables.py [--check]

Each table of ``TABLES`` (a material's ``ParameterSpec.markdown()``, or OpenPBR's tables
with each input's status) is placed between the markers ``<!-- parameters: NAME -->`` and
``<!-- end parameters -->`` of its page. ``--check`` only reports (exit 1) a page whose
table is out of date (``tests/test_parameter_spec.py`` runs it).
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from adobe_bsdf.materials import MATERIALS, openpbr

DOCS = Path(__file__).resolve().parent
#: each table by name: its page and the function that writes it
TABLES = {
    "AdobeStandardMaterial": ("asm.md", MATERIALS["AdobeStandardMaterial"].parameters.markdown),
    "OpenPBRSurface": ("openpbr.md", lambda: openpbr.parameters.status_markdown(
        openpbr.PARAMETERS)),
    "OpenPBRDraft": ("openpbr.md", lambda: openpbr.parameters.status_markdown(
        openpbr.DRAFT_PARAMETERS)),
    "OpenPBRVersions": ("openpbr.md", openpbr.parameters.versions_markdown),
}
#: the page of each table
PAGES = {name: page for name, (page, _) in TABLES.items()}


def _block(name: str) -> str:
    table = TABLES[name][1]()
    return (f"<!-- parameters: {name} (written by docs/parameter_tables.py) -->\n{table}"
            "<!-- end parameters -->")


def updated(name: str, text: str) -> str:
    """``text`` of the page with the table of material ``name`` rewritten."""
    pattern = re.compile(rf"<!-- parameters: {name}\b.*?-->\n.*?<!-- end parameters -->", re.S)
    if not pattern.search(text):
        raise ValueError(f"the page of {name} has no <!-- parameters: {name} --> block")
    return pattern.sub(lambda _: _block(name), text)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="only check, write nothing")
    args = parser.parse_args(argv)
    stale = []
    for name, page in PAGES.items():
        path = DOCS / page
        text = path.read_text(encoding="utf-8")
        new = updated(name, text)
        if new != text:
            stale.append(f"{page} ({name})")
            if not args.check:
                path.write_text(new, encoding="utf-8")
    if args.check and stale:
        print(f"out of date: {', '.join(stale)} (run python docs/parameter_tables.py)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
