"""OpenPBR Surface materials in MaterialX documents (``.mtlx``): read every
``open_pbr_surface`` node into an ``OpenPBRSurface``, write materials back (the policies are
in ``docs/materialx.md``).

Public API
----------
``load_mtlx(path, spec=None)``                                        -> ``MtlxResult``
``save_mtlx(materials, path, colorspace="lin_rec709")``               -> the path written
``MtlxResult``    a read-only mapping {name: ``OpenPBRSurface``}; ``records[name]`` is the
                  ``MtlxMaterial`` with the parameters used, the colour spaces converted and
                  the warnings raised
``MtlxWarning``   the category of the importer's own warnings (connected inputs, clipped
                  colours, nodedef defaults that differ from the library's)
``COLOR_SPACES``  {MaterialX colour space: (colour-science colourspace, decoding)}

The OpenPBR version of a node is the document's where it says one (the node's ``version``,
else its nodedef's: "1.2" is the development branch, ``spec="dev_1.2"``; earlier ones the
release, "1.1.1"), else ``load_mtlx``'s ``spec`` (default "1.1.1"); ``save_mtlx`` writes
``version="1.2"`` on the nodes of a dev_1.2 material.

Reading never evaluates anything of the document: an input connected to a node, a node
graph or an interface name is replaced by its own ``value`` (or the nodedef's default), with
a warning. Values are parsed from the document's strings as float64 (MaterialX's own
``getValue`` rounds to float32), and written with ``repr``, so ``save_mtlx`` then
``load_mtlx`` gives back identical parameters in the working space ``lin_rec709``.

The ``materialx`` package is imported inside the functions (``pip install materialx``, or
the ``mtlx`` extra); colour spaces are converted with colour-science's ``RGB_to_RGB`` and
the Bradford chromatic adaptation (``matrix_RGB_to_RGB``, the matrix its ``RGB_to_RGB``
applies), the transform of MaterialX's own colour-management nodes (``cmlib``), so a colour
reads as a MaterialX renderer shows it.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.materials.openpbr import PARAMETERS, OpenPBRSurface
from adobe_bsdf.materials.openpbr.material import versions
from adobe_bsdf.materials.openpbr.parameters import DEV_1_2
from adobe_bsdf.spectral import colour_science

__all__ = ["load_mtlx", "save_mtlx", "MtlxResult", "MtlxMaterial", "MtlxWarning",
           "COLOR_SPACES", "WORKING_SPACE", "CHROMATIC_ADAPTATION", "ROUND_OFF"]

#: the MaterialX version string of the development branch's nodes
DEV_VERSION = "1.2"
#: the node category read and written, and its standard declaration
CATEGORY = "open_pbr_surface"
NODEDEF = "ND_open_pbr_surface_surfaceshader"

#: the library's colour space: linear Rec. 709 primaries, D65 white (MaterialX's default)
WORKING_SPACE = "lin_rec709"

#: MaterialX colour space -> (colour-science colourspace of its primaries and white point,
#: decoding to linear: None, "sRGB" (IEC 61966-2-1 piecewise curve) or a pure gamma); the
#: spaces MaterialX's colour-management library converts to lin_rec709
COLOR_SPACES = {
    "lin_rec709": ("ITU-R BT.709", None),
    "srgb_texture": ("ITU-R BT.709", "sRGB"),
    "g22_rec709": ("ITU-R BT.709", 2.2),
    "g18_rec709": ("ITU-R BT.709", 1.8),
    "rec709_display": ("ITU-R BT.709", 2.4),
    "acescg": ("ACEScg", None),
    "g22_ap1": ("ACEScg", 2.2),
    "lin_adobergb": ("Adobe RGB (1998)", None),
    "adobergb": ("Adobe RGB (1998)", 563.0 / 256.0),
    "lin_displayp3": ("Display P3", None),
    "srgb_displayp3": ("Display P3", "sRGB"),
}

#: chromatic adaptation between white points (ACEScg's D60 to Rec. 709's D65): Bradford,
#: whose matrix is the one MaterialX's cmlib applies (acescg -> lin_rec709 agrees to 1e-12)
CHROMATIC_ADAPTATION = "Bradford"

#: a converted colour outside its range by at most this much is round-off of the 3x3 matrix
#: (ACEScg white becomes 1 + 1e-15): clipped without a warning
ROUND_OFF = 1e-12

#: MaterialX value types of each kind of input
_TYPES = {"real": "float", "color": "color3", "vector": "vector3", "bool": "boolean"}
#: the attributes that connect an input to something this reader does not evaluate
_CONNECTIONS = ("nodename", "nodegraph", "output", "interfacename")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_INTEGER = re.compile(r"[+-]?\d+")
#: scales tried by ``_exact_vector`` (deterministic; index 0 is the vector itself)
_SCALES = 1.0 + np.arange(4096) / 4096.0


class MtlxWarning(UserWarning):
    """A MaterialX document was read with a substitution: a connected input replaced by a
    value, a colour clipped into its range, a nodedef default unlike the library's."""


@dataclass(frozen=True)
class MtlxMaterial:
    """One material of a document, as ``load_mtlx`` read it.

    Attributes
    ----------
    name : str
        Its key in the ``MtlxResult``: the ``surfacematerial``'s name, else the shader's.
    node : str
        Name path of the ``open_pbr_surface`` node.
    material : OpenPBRSurface
    params : dict
        Every input passed to ``OpenPBRSurface``: float, tuple of 3 floats or bool, colours
        in lin_rec709 after conversion and clipping.
    colorspaces : dict
        {colour input read from the document: its MaterialX colour space}.
    original : dict
        {colour input converted or clipped: the 3 values as the document writes them}.
    warnings : tuple of str
        Every warning raised while reading this material (the importer's and
        ``OpenPBRSurface``'s, such as inputs not modelled yet).
    """

    name: str
    node: str
    material: OpenPBRSurface
    params: dict
    colorspaces: dict
    original: dict
    warnings: tuple

    @property
    def conversion(self) -> str:
        """The colour-space conversions applied, e.g. ``"acescg -> lin_rec709 (Bradford)"``,
        or ``"none"``."""
        spaces = sorted({s for s in self.colorspaces.values() if s != WORKING_SPACE})
        return "; ".join(_describe(s) for s in spaces) or "none"


class MtlxResult(Mapping):
    """The materials of one document: a read-only mapping {name: ``OpenPBRSurface``}, in
    document order (``surfacematerial`` nodes first, then shaders no material references).

    Attributes
    ----------
    path : Path
    colorspace : str
        The document's colour space (lin_rec709 where it declares none).
    records : dict of str to MtlxMaterial
    """

    def __init__(self, path: Path, colorspace: str, records: dict):
        self.path, self.colorspace, self.records = path, colorspace, dict(records)

    def __getitem__(self, name: str) -> OpenPBRSurface:
        return self.records[name].material

    def __iter__(self):
        return iter(self.records)

    def __len__(self) -> int:
        return len(self.records)

    @property
    def warnings(self) -> tuple:
        """Every warning of the document, once each, in order."""
        return tuple(dict.fromkeys(w for r in self.records.values() for w in r.warnings))

    def __repr__(self) -> str:
        return f"MtlxResult({str(self.path)!r}, {list(self.records)})"


# -- MaterialX and its libraries --------------------------------------------------------------
def _materialx():
    try:
        import MaterialX
    except ImportError as exc:
        raise ImportError("reading and writing .mtlx files needs the 'materialx' package: "
                          "pip install materialx (or pip install adobe_bsdf[mtlx])") from exc
    return MaterialX


@lru_cache(maxsize=1)
def _library():
    """MaterialX's standard data libraries, as shipped inside the ``materialx`` package."""
    mx = _materialx()
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    if lib.getNodeDef(NODEDEF) is None:
        raise ImportError(f"the installed materialx package ({mx.__version__}) has no "
                          f"{NODEDEF}: allowed materialx >= 1.39")
    return lib


# -- colour spaces ------------------------------------------------------------------------------
def _describe(space: str) -> str:
    primaries, decoding = COLOR_SPACES[space]
    steps = []
    if decoding is not None:
        steps.append("sRGB decoding" if decoding == "sRGB" else f"gamma {decoding:g}")
    if primaries != COLOR_SPACES[WORKING_SPACE][0]:
        steps.append(f"{primaries} to ITU-R BT.709, {CHROMATIC_ADAPTATION}")
    return f"{space} -> {WORKING_SPACE} ({', '.join(steps)})"


@lru_cache(maxsize=len(COLOR_SPACES))
def _matrix(space: str) -> np.ndarray:
    """The 3x3 matrix from the linear RGB of ``space`` to lin_rec709: colour-science's
    ``matrix_RGB_to_RGB`` (what its ``RGB_to_RGB`` applies) with the Bradford adaptation."""
    colour = colour_science()
    return np.asarray(colour.matrix_RGB_to_RGB(
        COLOR_SPACES[space][0], COLOR_SPACES[WORKING_SPACE][0],
        chromatic_adaptation_transform=CHROMATIC_ADAPTATION), dtype=np.float64)


def _to_working(rgb: np.ndarray, space: str) -> np.ndarray:
    """``rgb`` of MaterialX colour space ``space`` in lin_rec709."""
    colour = colour_science()
    primaries, decoding = COLOR_SPACES[space]
    if decoding == "sRGB":
        rgb = colour.cctf_decoding(rgb, function="sRGB")
    elif decoding is not None:
        rgb = np.maximum(rgb, 0.0) ** decoding
    rgb = np.asarray(rgb, dtype=np.float64)
    if primaries == COLOR_SPACES[WORKING_SPACE][0]:
        return rgb
    return rgb @ _matrix(space).T


def _from_working(rgb: np.ndarray, space: str) -> np.ndarray:
    """The inverse of ``_to_working``: lin_rec709 into ``space`` (the inverse matrix, so a
    round trip returns the colour to round-off: colour-science's published RGB <-> XYZ
    matrices of some spaces are not exact inverses of each other)."""
    colour = colour_science()
    primaries, decoding = COLOR_SPACES[space]
    if primaries != COLOR_SPACES[WORKING_SPACE][0]:
        rgb = np.linalg.solve(_matrix(space), np.asarray(rgb, dtype=np.float64))
    rgb = np.maximum(np.asarray(rgb, dtype=np.float64), 0.0)
    if decoding == "sRGB":
        return np.asarray(colour.cctf_encoding(rgb, function="sRGB"), dtype=np.float64)
    if decoding is not None:
        return rgb ** (1.0 / decoding)
    return rgb


# -- reading ------------------------------------------------------------------------------------
def load_mtlx(path, *, spec: str | None = None, darkening_variant: str | None = None,
              haze_model: str | None = None) -> MtlxResult:
    """Every ``open_pbr_surface`` of the MaterialX document at ``path``.

    Parameters
    ----------
    path : str or Path
    spec : one of ``materials.openpbr.SPECS`` or None
        The OpenPBR version of the nodes whose document says none (None: "1.1.1"); a node
        whose ``version`` (or its nodedef's) says one follows it, and a ``spec`` against it
        is a ``ValueError``.
    darkening_variant, haze_model : deprecated
        Passed to every ``OpenPBRSurface`` (``OpenPBRSurface``: aliases of ``spec``).

    Returns
    -------
    MtlxResult
        {name: OpenPBRSurface}, plus per material the parameters used, the colour-space
        conversion and the warnings. Warnings are also raised (``MtlxWarning`` for the
        importer's own; ``OpenPBRSurface``'s with their category), each prefixed by the file
        and the node.

    Raises
    ------
    FileNotFoundError
        No file at ``path``.
    ValueError
        Naming the file (and the node and input where there is one): malformed XML, no
        ``open_pbr_surface``, a material whose shader is another node type, an input unknown
        to OpenPBR (or of dev_1.2 on a node of the release), a type unlike the nodedef's, an
        unparsable or out-of-range value, an unknown colour space, a ``spec`` against the
        document's version.
    """
    spec, barla = versions(spec, darkening_variant, haze_model, stacklevel=3)
    mx = _materialx()
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such MaterialX file")
    doc = mx.createDocument()
    try:
        mx.readFromXmlFile(doc, str(path))
    except (mx.ExceptionParseError, mx.ExceptionFileMissing) as exc:
        raise ValueError(f"{path}: not a readable MaterialX document: {exc}") from exc
    doc.setDataLibrary(_library())
    options = {"spec": spec, "haze_model": "barla2018" if barla else None}

    entries = []  # (name, shader node)
    for material in doc.getMaterialNodes():
        if material.getCategory() != "surfacematerial":
            continue
        shader = _shader_of(material, path, mx)
        if shader is not None:
            entries.append((material.getName(), shader))
    referenced = {shader.getNamePath() for _, shader in entries}
    for element in doc.traverseTree():
        if (element.isA(mx.Node) and element.getCategory() == CATEGORY
                and element.getNamePath() not in referenced):
            entries.append((element.getName(), element))
    if not entries:
        found = sorted({e.getCategory() for e in doc.traverseTree() if e.isA(mx.Node)})
        raise ValueError(f"{path}: no {CATEGORY} node in the document (its nodes: "
                         f"{', '.join(found) or 'none'})")

    records, read = {}, {}
    for name, shader in entries:
        key = _unique(name, records)
        node = shader.getNamePath()
        if node not in read:
            read[node] = _read_shader(shader, path, mx, options)
        material, params, spaces, original, messages = read[node]
        records[key] = MtlxMaterial(key, node, material, params, spaces, original,
                                    tuple(text for text, _ in messages))
    for *_, messages in read.values():
        for text, category in messages:
            warnings.warn(text, category, stacklevel=2)
    return MtlxResult(path, doc.getActiveColorSpace() or WORKING_SPACE, records)


def _unique(name: str, taken) -> str:
    """``name``, or ``name_2``, ``name_3``, ... for the second, third, ... use of it."""
    if name not in taken:
        return name
    k = 2
    while f"{name}_{k}" in taken:
        k += 1
    return f"{name}_{k}"


def _shader_of(material, path: Path, mx):
    """The ``open_pbr_surface`` node a ``surfacematerial`` references, None where its
    ``surfaceshader`` input is absent or empty."""
    where = f"{path}: surfacematerial {material.getNamePath()!r}"
    link = material.getInput("surfaceshader")
    if link is None or not any(link.getAttribute(a) for a in _CONNECTIONS):
        return None
    shaders = mx.getShaderNodes(material)
    if not shaders:
        target = link.getNodeName() or link.getNodeGraphString()
        raise ValueError(f"{where}: its surfaceshader input names {target!r}, which is not a "
                         "surface shader node of the document")
    shader = shaders[0]
    if shader.getCategory() != CATEGORY:
        raise ValueError(f"{where}: its surface shader {shader.getNamePath()!r} is a "
                         f"{shader.getCategory()!r} node; allowed: {CATEGORY!r} (the only "
                         "shader this reader maps)")
    return shader


def _nodedef(shader, where: str):
    """The declaration of ``shader``: its own match, else (an extension input or a wrong type
    defeats MaterialX's matching) the declaration of its category, type and version."""
    nodedef = shader.getNodeDef()
    if nodedef is not None:
        return nodedef
    doc = shader.getDocument()
    if shader.getNodeDefString():
        nodedef = doc.getNodeDef(shader.getNodeDefString())
        if nodedef is None:
            raise ValueError(f"{where}: its nodedef {shader.getNodeDefString()!r} is not "
                             "declared in the document or MaterialX's libraries")
        return nodedef
    candidates = [nd for nd in doc.getMatchingNodeDefs(shader.getQualifiedName(CATEGORY))
                  if nd.getType() == shader.getType()]
    version = shader.getVersionString()
    if version:
        matching = [nd for nd in candidates if nd.getVersionString() == version]
        # the development branch's version has no nodedef in MaterialX's libraries: the
        # release's declares its inputs, dev_1.2's own take the library's defaults
        candidates = matching or (candidates if _version_spec(version) == "dev_1.2" else [])
    if not candidates:
        raise ValueError(f"{where}: no nodedef declares an {CATEGORY} of type "
                         f"{shader.getType()!r}" + (f" and version {version!r}" if version
                                                    else "") + "; allowed: 'surfaceshader'")
    defaults = [nd for nd in candidates if nd.getDefaultVersion()]
    return (defaults or candidates)[0]


def _version_spec(version: str) -> str:
    """The ``spec`` of a MaterialX version string of OpenPBR: "1.2" and later the development
    branch, earlier ones the release."""
    parts = re.findall(r"\d+", version)[:2]
    major_minor = tuple(int(x) for x in parts) + (0,) * (2 - len(parts))
    return "dev_1.2" if major_minor >= (1, 2) else "1.1.1"


def _node_spec(shader, nodedef, spec, where: str):
    """The ``spec`` a node follows: its own ``version``, else its nodedef's where that
    says one, else ``spec`` (None: "1.1.1")."""
    said = shader.getVersionString() or nodedef.getVersionString()
    if not said:
        return spec or "1.1.1"
    found = _version_spec(said)
    if spec is not None and spec != found:
        raise ValueError(f"{where}: the document's OpenPBR version {said!r} is spec = "
                         f"{found!r}, against spec = {spec!r}: allowed the document's "
                         "(or pass no spec)")
    return found


def _parse(text: str, type_: str, where: str):
    """A MaterialX value string of ``type_`` as float, tuple of 3 floats, int or bool."""
    text = text.strip()
    if type_ == "boolean":
        if text in ("true", "false"):
            return text == "true"
    elif type_ == "integer":
        if _INTEGER.fullmatch(text):
            return int(text)
    elif type_ == "float":
        if _NUMBER.fullmatch(text):
            return float(text)
    elif type_ in ("color3", "vector3"):
        parts = [s.strip() for s in text.split(",")]
        if len(parts) == 3 and all(_NUMBER.fullmatch(s) for s in parts):
            return tuple(float(s) for s in parts)
    else:
        raise ValueError(f"{where}: type {type_!r} is not read; allowed: float, integer, "
                         "boolean, color3, vector3")
    raise ValueError(f"{where}: value {text!r} is not a {type_}")


def _same(a, b) -> bool:
    """Bit-for-bit equality of two validated values (so -0.0 differs from 0.0)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@lru_cache(maxsize=1)
def _defaults() -> dict:
    return PARAMETERS.validate({})


def _read_shader(shader, path: Path, mx, options):
    """(material, params, colorspaces, original, messages) of one ``open_pbr_surface``."""
    where = f"{path}: node {shader.getNamePath()!r}"
    messages = []

    def warn(text, category=MtlxWarning):
        messages.append((f"{where}: {text}", category))

    nodedef = _nodedef(shader, where)
    options = dict(options, spec=_node_spec(shader, nodedef, options["spec"], where))
    inputs = [name for name in PARAMETERS.parameters
              if options["spec"] != "1.1.1" or name not in DEV_1_2]
    declared = {i.getName(): i for i in nodedef.getActiveInputs()}
    unknown = [i.getName() for i in shader.getInputs() if i.getName() not in inputs]
    if unknown:
        dev = [name for name in unknown if name in DEV_1_2]
        raise ValueError(f"{where}: input(s) {unknown} unknown to OpenPBR Surface"
                         + (f" 1.1.1 (the node's version; {dev} are dev_1.2's)" if dev
                            else "") + f"; allowed: {inputs}")
    params, spaces, original = {}, {}, {}
    for p in (PARAMETERS[name] for name in inputs):
        at = f"{where}, input {p.name!r}"
        decl = declared.get(p.name)
        type_ = decl.getType() if decl is not None else _TYPES[p.kind]
        default, default_space = p.default, WORKING_SPACE
        if decl is not None and decl.getValueString():
            default = _parse(decl.getValueString(), type_, f"{at} (its nodedef default)")
            default_space = decl.getActiveColorSpace() or WORKING_SPACE
        inp = shader.getInput(p.name)
        if inp is not None and inp.getType() != type_:
            raise ValueError(f"{at}: type {inp.getType()!r}; allowed: {type_!r} (the "
                             "nodedef's)")
        if inp is not None and inp.getValueString():
            text, space, from_doc = inp.getValueString(), inp.getActiveColorSpace(), True
        else:
            text, space, from_doc = None, default_space, False
        if inp is not None:
            links = [f'{a}="{inp.getAttribute(a)}"' for a in _CONNECTIONS if inp.getAttribute(a)]
            used = "its own value " + text if from_doc else f"the default {default!r}"
            if links:
                warn(f"input {p.name!r} is connected ({', '.join(links)}), which is not "
                     f"evaluated: {used} is used")
            elif not from_doc:
                warn(f"input {p.name!r} has no value: {used} is used")
        value = _parse(text, type_, at) if from_doc else default
        if p.kind == "color":
            value, checked = _colour(p, value, space or WORKING_SPACE, at, original, warn)
            if from_doc:
                spaces[p.name] = space or WORKING_SPACE
        else:
            try:
                checked = p.validate(value)
            except ValueError as exc:
                raise ValueError(f"{at}: {exc}") from exc
        if not from_doc and not _same(checked, _defaults()[p.name]):
            warn(f"input {p.name!r}: the nodedef's default {value!r} differs from the "
                 f"library's {p.default!r}: the nodedef's is used")
        params[p.name] = value

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            material = OpenPBRSurface(**params, **options)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from exc
    for w in caught:
        warn(str(w.message), w.category)
    return material, params, spaces, original, messages


def _colour(p, value, space, at, original, warn):
    """A colour input's ``value`` (any finite colour) in lin_rec709, clipped into its hard
    range, with a warning where it moved by more than ``ROUND_OFF``; returns (the value as
    a tuple, or as read where nothing changed; the validated array)."""
    if space not in COLOR_SPACES:
        raise ValueError(f"{at}: colorspace {space!r} is unknown; allowed: "
                         f"{', '.join(COLOR_SPACES)}")
    try:
        rgb = _params.color(p.name, value)
    except ValueError as exc:
        raise ValueError(f"{at}: {exc}") from exc
    converted = rgb if space == WORKING_SPACE else _to_working(rgb, space)
    lo, hi = p.hard
    clipped = np.clip(converted, lo, hi)
    if np.any(np.abs(converted - clipped) > ROUND_OFF):
        shown = (f"{_triple(rgb)} in {space} is {_triple(converted)} in {WORKING_SPACE}, "
                 if space != WORKING_SPACE else f"{_triple(rgb)} is ")
        warn(f"input {p.name!r} = {shown}outside the allowed range {p.range_text}: clipped "
             f"to {_triple(clipped)}")
    elif space == WORKING_SPACE:
        return value, p.validate(value)
    original[p.name] = tuple(float(x) for x in rgb)
    result = tuple(float(x) for x in clipped)
    return result, p.validate(result)


def _triple(x) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in np.broadcast_to(x, 3)) + ")"


# -- writing ------------------------------------------------------------------------------------
def save_mtlx(materials, path, colorspace: str = WORKING_SPACE) -> Path:
    """Write ``materials`` as a MaterialX document: per material one ``open_pbr_surface``
    node ``SR_<name>`` with the inputs that differ from the defaults, and a
    ``surfacematerial`` ``<name>`` referencing it.

    Parameters
    ----------
    materials : OpenPBRSurface or mapping of str to OpenPBRSurface
        A single material is named ``"material"``; names must be valid MaterialX names.
    path : str or Path
    colorspace : one of ``COLOR_SPACES``
        The document's colour space; colours are converted into it from lin_rec709. With
        lin_rec709 (the default) ``load_mtlx`` gives back identical parameters; with another
        space, equal to round-off of the conversion.

    Returns
    -------
    Path

    Raises
    ------
    ValueError
        An unknown colour space, a name MaterialX does not allow, a value that is not an
        OpenPBRSurface, a parameter holding an array of values (a texture) rather than one.
    """
    mx = _materialx()
    if colorspace not in COLOR_SPACES:
        raise ValueError(f"colorspace = {colorspace!r} is unknown; allowed: "
                         f"{', '.join(COLOR_SPACES)}")
    if isinstance(materials, OpenPBRSurface):
        materials = {"material": materials}
    if not isinstance(materials, Mapping) or not materials:
        raise ValueError(f"materials = {type(materials).__name__}: allowed an OpenPBRSurface "
                         "or a non-empty mapping of names to them")
    names = [str(n) for n in materials] + [f"SR_{n}" for n in materials]
    for name, material in materials.items():
        if not isinstance(name, str) or not name or mx.createValidName(name) != name:
            raise ValueError(f"material name {name!r}: allowed a MaterialX name (letters, "
                             "digits and underscores, not starting with a digit)")
        if not isinstance(material, OpenPBRSurface):
            raise ValueError(f"materials[{name!r}] = {type(material).__name__}: allowed an "
                             "OpenPBRSurface")
    if len(set(names)) != len(names):
        raise ValueError(f"material names {list(materials)}: the shader names SR_<name> "
                         "must not repeat a material name")
    doc = mx.createDocument()
    if colorspace != WORKING_SPACE:
        doc.setColorSpace(colorspace)
    for name, material in materials.items():
        _check_options(name, material)
        shader = doc.addNode(CATEGORY, f"SR_{name}", "surfaceshader")
        if material.spec == "dev_1.2":
            shader.setVersionString(DEV_VERSION)
        for p in PARAMETERS:
            value = material.params.get(p.name)
            if value is None or _same(value, _defaults()[p.name]):
                continue
            shader.addInput(p.name, _TYPES[p.kind]).setValueString(
                _format(p, value, colorspace, name))
        node = doc.addNode("surfacematerial", name, "material")
        node.addInput("surfaceshader", "surfaceshader").setNodeName(f"SR_{name}")
    path = Path(path)
    mx.writeToXmlFile(doc, str(path))
    return path


def _check_options(name: str, material) -> None:
    if material.spec == "dev_1.2" and material.haze_model != "dev_1.2":
        warnings.warn(f"save_mtlx: material {name!r} has haze_model = "
                      f"{material.haze_model!r}, a choice of this library that MaterialX "
                      "does not store: pass it to load_mtlx", MtlxWarning, stacklevel=3)


def _format(p, value, colorspace: str, name: str) -> str:
    """The value string of one input: ``repr`` of each float64 (exact on reading)."""
    if p.kind == "bool":
        return "true" if value else "false"
    arr = np.asarray(value, dtype=np.float64)
    shape = () if p.kind == "real" else (3,)
    if arr.shape != shape:
        raise ValueError(f"material {name!r}: {p.name} has shape {arr.shape}; a MaterialX "
                         f"input holds one value (shape {shape})")
    if p.kind == "color" and colorspace != WORKING_SPACE:
        arr = _from_working(arr, colorspace)
    if p.kind == "vector":
        arr = _exact_vector(p, arr)
    return ", ".join(repr(float(x)) for x in arr.reshape(-1))


def _exact_vector(p, v: np.ndarray) -> np.ndarray:
    """A 3-vector w whose normalisation is exactly the normalised ``v`` (normalising is not
    idempotent to the last bit, so ``v`` itself may not read back as ``v``)."""
    candidates = v * _SCALES[:, None]
    hits = np.flatnonzero(np.all(p.validate(candidates) == v, axis=-1))
    for i in hits:
        if _same(p.validate(candidates[i]), v):
            return candidates[i]
    warnings.warn(f"save_mtlx: {p.name} = {tuple(v)} reads back within 1 ulp, not exactly",
                  MtlxWarning, stacklevel=4)
    return v
