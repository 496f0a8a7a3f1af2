"""Read a folder of OpenPBR MaterialX examples and write ``docs/materialx.md``: the importer's
API and policies (the prose below) and, measured, a table of every example with the
materials it holds, the colour conversion applied, the warnings raised and the time to read.

    python -m benchmarks.mtlx_report EXAMPLES_DIR [--out DIR]
"""

from __future__ import annotations

import argparse
import datetime
import time
import warnings
from pathlib import Path

from adobe_bsdf.io import COLOR_SPACES, load_mtlx
from adobe_bsdf.io.mtlx import CHROMATIC_ADAPTATION, ROUND_OFF

DOCS = Path(__file__).resolve().parents[1] / "docs"

PROSE = """\
# MaterialX import and export

`adobe_bsdf.io` reads the `open_pbr_surface` nodes of a MaterialX document (`.mtlx`) into
`OpenPBRSurface` materials and writes materials back. It needs the `materialx` package
(`pip install materialx`, or the `mtlx` extra), imported only when a function runs; the
OpenPBR nodedef and the colour-management nodes come from the standard data libraries
shipped inside that package (no network).

```python
from adobe_bsdf.io import load_mtlx, save_mtlx

result = load_mtlx("gold.mtlx")          # MtlxResult: a mapping {name: OpenPBRSurface}
material = result["Gold"]
record = result.records["Gold"]         # MtlxMaterial
record.params, record.colorspaces, record.original, record.conversion, record.warnings
save_mtlx({"Gold": material}, "copy.mtlx")                 # lin_rec709, exact round trip
save_mtlx(material, "aces.mtlx", colorspace="acescg")      # one material, named "material"
```

- `load_mtlx(path, spec=None)`: every `open_pbr_surface` of the document, each following the
  OpenPBR version its document says (the node's `version`, else its nodedef's: 1.2 is
  `spec="dev_1.2"`, earlier ones the release "1.1.1"), else `spec` (None: "1.1.1"); a
  `spec` against the document's version raises. The deprecated `darkening_variant` and
  `haze_model` of `OpenPBRSurface` are passed on for one release.
- `MtlxResult`: a read-only mapping {name: `OpenPBRSurface`} in document order;
  `.records[name]` (an `MtlxMaterial`), `.warnings` (all, once each), `.colorspace` (the
  document's), `.path`.
- `MtlxMaterial`: `name`; `node` (name path of the shader); `material`; `params` (every
  input passed to `OpenPBRSurface`, colours after conversion); `colorspaces` ({colour input
  read from the file: its colour space}); `original` ({colour input converted or clipped:
  the file's values}); `conversion` (e.g. `acescg -> lin_rec709 (ACEScg to ITU-R BT.709,
  Bradford)`, or `none`); `warnings`.
- `save_mtlx(materials, path, colorspace="lin_rec709")`: one `open_pbr_surface` `SR_<name>`
  and one `surfacematerial` `<name>` per material; returns the path.
- `MtlxWarning`: the category of the importer's own warnings; `COLOR_SPACES`: the MaterialX
  colour spaces read and written.

## Names

A material is named by the `surfacematerial` that references its shader; a shader that no
material references is named by its node. Materials come first, in document order, then the
unreferenced shaders (nested node graphs included). Two materials that reference one shader
are two entries holding the same `OpenPBRSurface`. A name used again gets `_2`, `_3`, ... in
that order.

## Defaults

An input the document does not set takes the default of the shader's nodedef: the node's
own match (`node.getNodeDef()`), else the nodedef of its category, type and version, which
may be declared in the document itself. The standard `ND_open_pbr_surface_surfaceshader`
(OpenPBR 1.1.1) agrees with the library's parameter table on every default (a test checks
it); its four geometry vectors have no value but `defaultgeomprop` `Nworld` / `Tworld`,
which in the library's local shading frame are the normal (0, 0, 1) and tangent (1, 0, 0).
Where a document's own nodedef gives another default, the nodedef's is used and a warning
says so. The development branch's four inputs (`specular_haze`, `specular_haze_spread`,
`specular_retroreflectivity`, `emission_weight`) are read on nodes of version 1.2 (an input of
theirs on a node of the release is a `ValueError` naming it) and written on the nodes of a
`spec="dev_1.2"` material, which `save_mtlx` marks `version="1.2"`; no MaterialX library
declares that version yet, so its inputs the release declares take the release's nodedef
defaults and its own ones the library's.

## Colour spaces

Every colour input (`color3`) is converted from its colour space to the library's linear
Rec. 709 (`lin_rec709`, D65). The colour space is the input's `colorspace`, else its node's,
else the document's, else `lin_rec709` (MaterialX's default working space); nodedef defaults
are in their nodedef's space. The spaces are the ones MaterialX's own colour-management
library converts:

{spaces}

The transfer function is decoded first (the piecewise sRGB curve of IEC 61966-2-1, or a pure
gamma of negative values clamped to 0), then the primaries are changed with colour-science's
`matrix_RGB_to_RGB` (the matrix its `RGB_to_RGB` applies) and the **{cat}** chromatic
adaptation from the space's white to D65 (ACEScg's white is ACES's ≈ D60). Bradford is
chosen because it is the transform of MaterialX's own `acescg_to_lin_rec709` node: the
colour-science matrix matches the one MaterialX publishes to 1e-11, so a colour reads as a
MaterialX renderer shows it. `lin_rec709` values are not touched (bit for bit). An unknown
colour space raises `ValueError` naming the file, the node and the input.

**Gamut and range.** A converted colour can leave [0, 1] (a saturated ACEScg colour lies
outside Rec. 709), and real documents also write colours beyond the parameter table's range
in the file itself (the examples below: `specular_color` 1.013, `subsurface_radius_scale`
3). Colours are therefore clipped to the input's hard range (`[0, 1]`; `emission_color`
`[0, ∞)`) after conversion, with an `MtlxWarning` naming the input, the file's value, the
converted value and the clipped one; `MtlxMaterial.original` keeps the file's value. A
colour outside its range by at most {round_off} (round-off of the matrix: ACEScg white
becomes 1 + 1e-15) is clipped silently. Non-finite colours raise.

## What is not evaluated

Nothing from a document is executed. An input connected to a node, a node graph or an
interface name (`nodename`, `nodegraph`, `output`, `interfacename`: a texture, a procedural)
cannot be evaluated: its own `value` is used if it has one, else the nodedef default, and an
`MtlxWarning` names the input, the connection and the value used. An input with no value is
treated the same way. Inputs that `OpenPBRSurface` accepts but does not model yet (thin film,
media, thin walls, normal maps: `PLANNED`) make it warn when set away from their default:
that warning is raised again with the file and node in front, and recorded in
`MtlxMaterial.warnings`.

## Bad input

Every `ValueError` names the file, and the node and input where there is one:

- malformed XML (with the parser's message) or a file that is not a MaterialX document;
- no `open_pbr_surface` in the document; a `surfacematerial` whose shader is another node
  type (`standard_surface`, ...) or a missing node; no nodedef for the node's type or version;
- an input unknown to OpenPBR Surface (listing the allowed names); a type unlike the
  nodedef's (`float`, `color3`, `vector3`, `boolean`, `integer`); a value string that does
  not parse as that type (`nan`, `1,5`, two components); an unknown colour space;
- a real or boolean value outside the parameter table's hard range (the parameter table's
  message: name, value, allowed range); a zero vector; an index outside the energy tables
  (`OpenPBRSurface`'s message).

A missing file raises `FileNotFoundError`.

## Writing

`save_mtlx` writes only the inputs that differ from the library's defaults (bit for bit:
`-0.0` is written), each float64 with `repr`: MaterialX's own value formatting keeps 6
significant digits (0.30000000000000004 would be written 0.3) and its `getValue` reads
float32, so the reader parses and the writer formats the value strings itself. With the
default `colorspace="lin_rec709"`, `load_mtlx` gives back identical parameters (tests: random
parameter sets and every example). Another colour space converts the colours with the
inverse of the reading matrix and re-encodes them: the round trip is then exact to round-off
(1e-13). A geometry vector is written as a multiple of itself whose normalisation gives the
stored unit vector exactly (normalising is not idempotent to the last bit). A parameter
holding an array (a texture of values) cannot be written and raises; the deprecated
`haze_model="barla2018"` is not stored (a warning says so).
"""


def _short(message: str) -> str:
    """A warning without its ``file: node 'x': `` prefix, for the table."""
    parts = message.split(": ", 2)
    text = parts[2] if len(parts) == 3 and parts[1].startswith("node ") else message
    return text.replace("|", "\\|").replace(" (docs/openpbr.md)", "")


def _decoding(decoding) -> str:
    if decoding is None:
        return "none"
    return "sRGB (IEC 61966-2-1)" if decoding == "sRGB" else f"gamma {decoding:g}"


def _table(folder: Path) -> tuple[str, int, int]:
    rows = ["| file | material | conversion | read (ms) | warnings |",
            "|---|---|---|---|---|"]
    files = sorted(folder.glob("*.mtlx"))
    loaded = 0
    for path in files:
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = load_mtlx(path)
        except ValueError as exc:
            rows.append(f"| `{path.name}` | — | — | — | **error**: {_short(str(exc))} |")
            continue
        ms = 1e3 * (time.perf_counter() - start)
        loaded += 1
        for name, record in result.records.items():
            notes = "<br>".join(_short(w) for w in record.warnings) or "none"
            conversion = record.conversion.split(" (")[0]
            rows.append(f"| `{path.name}` | {name} | {conversion} | {ms:.0f} | {notes} |")
    return "\n".join(rows) + "\n", loaded, len(files)


def run(folder: Path, out: Path | None = None) -> Path:
    start = time.perf_counter()
    table, loaded, total = _table(folder)
    spaces = "\n".join(["| MaterialX | colour-science primaries | decoding |", "|---|---|---|"]
                       + [f"| `{name}` | {primaries} | {_decoding(dec)} |"
                          for name, (primaries, dec) in COLOR_SPACES.items()])
    seconds = time.perf_counter() - start
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    head = (f"*The prose of this page is in `benchmarks/mtlx_report.py`; the table of examples "
            f"was generated by `python -m benchmarks.mtlx_report {folder.name}` on {now} in "
            f"{seconds:.1f} s; do not edit by hand.*\n\n")
    prose = (PROSE.replace("{spaces}", spaces).replace("{cat}", CHROMATIC_ADAPTATION)
             .replace("{round_off}", f"{ROUND_OFF:g}"))
    page = (head + prose
            + f"\n## The OpenPBR examples\n\n{loaded} of {total} documents of the folder "
            f"`{folder.name}` load (the OpenPBR project's example materials, OpenPBR 1.1.1, all "
            "in `acescg`). Warnings per material, without the file and node prefix:\n\n"
            + table)
    path = (out or DOCS) / "materialx.md"
    path.write_text(page, encoding="utf-8")
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("examples", type=Path, help="folder of .mtlx examples")
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    args = parser.parse_args(argv)
    print(run(args.examples, args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
