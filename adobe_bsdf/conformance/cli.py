"""``python -m adobe_bsdf conform REFERENCE --candidate CANDIDATE``: the command line of
``conformance.compare``.

REFERENCE, as words:

* a material with parameters: ``ASM roughness=0.3 metallic=1``, ``OpenPBR coat_weight=1``
  (a colour as ``base_color=0.8,0.5,0.2``);
* a lobe of ``adobe_bsdf.lobes`` with keyword arguments: ``Conductor alpha_x=0.3
  alpha_y=0.1 masking=separable``;
* a MaterialX file: ``material.mtlx`` (its first material, or ``material.mtlx NAME``);
* a case of ``python -m adobe_bsdf check`` (its name, or a part of it naming one case).

CANDIDATE: ``mitsuba:`` followed by a Mitsuba 3 plugin dictionary in JSON or its XML; or a
renderer's answer file (``--candidate answers.jsonl --request request.jsonl``), after
``--write-request request.jsonl`` wrote the queries (``conformance.files``).
"""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["reference_from_words", "candidate_from_text", "add_parser", "run"]

_MATERIALS = {"asm": "AdobeStandardMaterial", "adobestandardmaterial": "AdobeStandardMaterial",
              "openpbr": "OpenPBRSurface", "openpbrsurface": "OpenPBRSurface"}


def _value(text: str):
    """A number, a tuple of numbers (``a,b,c``), or the text itself."""
    try:
        parts = [float(x) for x in text.split(",")]
    except ValueError:
        return text
    return parts[0] if len(parts) == 1 else tuple(parts)


def _keywords(words) -> dict:
    out = {}
    for word in words:
        key, sep, value = word.partition("=")
        if not sep or not key:
            raise ValueError(f"{word!r}: parameters are given as name=value")
        out[key] = _value(value)
    return out


def reference_from_words(words):
    """The reference lobe or material named by ``words`` (the module docstring's forms;
    ``ValueError`` saying which forms exist where none fits)."""
    from adobe_bsdf import lobes, materials

    if not words:
        raise ValueError("no reference: name a material (ASM roughness=0.3), a lobe "
                         "(Conductor alpha_x=0.3), a .mtlx file or a check case")
    head, rest = words[0], list(words[1:])
    if head.lower() in _MATERIALS:
        return materials.MATERIALS[_MATERIALS[head.lower()]](**_keywords(rest))
    if head.endswith(".mtlx"):
        from adobe_bsdf.io import load_mtlx

        found = load_mtlx(Path(head))
        if not len(found):
            raise ValueError(f"{head}: the document holds no open_pbr_surface")
        name = rest[0] if rest else next(iter(found))
        if name not in found:
            raise ValueError(f"{head}: no material {name!r}; it holds {', '.join(found)}")
        return found[name]
    cls = getattr(lobes, head, None)
    if isinstance(cls, type):
        return cls(**_keywords(rest))
    from adobe_bsdf.validation.cases import cases

    text = " ".join(words)
    named = [c for c in cases() if c.name == text] or [
        c for c in cases() if text.lower() in c.name.lower()]
    if len(named) == 1:
        return named[0].make()
    if named:
        raise ValueError(f"{text!r} names {len(named)} check cases: "
                         + "; ".join(c.name for c in named[:8]))
    raise ValueError(f"{text!r} is no material (ASM, OpenPBR), lobe of adobe_bsdf.lobes, "
                     ".mtlx file or check case (python -m adobe_bsdf check --list)")


def candidate_from_text(text: str, request=None):
    """The candidate named by ``text``: ``mitsuba:`` and a plugin dictionary in JSON or its
    XML, or an answer file (``.jsonl``, ``.npz``) to the request file ``request``."""
    if text.endswith((".jsonl", ".npz")):
        if request is None:
            raise ValueError(f"--candidate {text}: an answer file needs --request, the "
                             "request file it answers")
        from adobe_bsdf.conformance.files import read_answers

        return read_answers(text, request)
    kind, sep, body = text.partition(":")
    if sep and kind == "mitsuba":
        from adobe_bsdf.validation.mitsuba import MitsubaBSDF

        body = body.strip()
        if body.startswith("{"):
            try:
                plugin = json.loads(body)
            except json.JSONDecodeError as exc:
                raise ValueError(f"--candidate {text!r}: not JSON ({exc})") from None
            return MitsubaBSDF(plugin)
        return MitsubaBSDF(body)
    raise ValueError(f"--candidate {text!r}: allowed mitsuba:JSON or mitsuba:XML (a Mitsuba 3 "
                     "plugin), or an answer file (.jsonl, .npz) with --request")


def add_parser(sub) -> None:
    p = sub.add_parser(
        "conform", help="judge a BSDF written elsewhere against the reference",
        description="Compare a candidate BSDF with a reference lobe or material of the "
        "library (docs/conformance.md) and print the verdict as a table. Exit code 1 if it "
        "does not conform.")
    p.add_argument("reference", nargs="+", metavar="REFERENCE",
                   help="ASM name=value..., OpenPBR name=value..., a lobe (Conductor "
                   "alpha_x=0.3 ...), a .mtlx file, or a check case")
    p.add_argument("--candidate", metavar="CANDIDATE",
                   help="a Mitsuba 3 plugin: mitsuba:'{\"type\": \"roughconductor\", ...}' "
                   "or mitsuba:'<bsdf type=...>...</bsdf>'; or a renderer's answer file "
                   "(.jsonl, .npz) with --request")
    p.add_argument("--write-request", metavar="FILE",
                   help="write the queries for a renderer to answer (.jsonl or .npz) and "
                   "exit")
    p.add_argument("--request", metavar="FILE",
                   help="the request file that --candidate answers")
    p.add_argument("--samples", type=int, default=100_000, metavar="N",
                   help="samples per view of each statistical test (default 100000)")
    p.add_argument("--view", nargs=2, type=float, action="append", metavar=("COS", "PHI"),
                   help="a view: cos theta_o and azimuth in radians (repeat; default: "
                   "conformance.default_views)")
    p.add_argument("--float32", action="store_true",
                   help="the candidate computes in float32: leave out ill-conditioned pairs")
    p.add_argument("--other-sampling", action="store_true",
                   help="the candidate samples another distribution than the reference")
    p.add_argument("--out", metavar="DIR", help="also write report.md and report.json there")


def run(args, prog: str) -> int:
    import sys

    from adobe_bsdf.conformance.compare import compare

    def fail(message):
        print(f"{prog} conform: error: {message}", file=sys.stderr)
        return 2
    if args.samples < 1000:
        return fail(f"--samples {args.samples}: allowed at least 1000")
    if (args.candidate is None) == (args.write_request is None):
        return fail("give --candidate (what to judge) or --write-request FILE (the queries "
                    "for a renderer), one of them")
    try:
        reference = reference_from_words(args.reference)
        views = _views(args.view)
        if args.write_request:
            from adobe_bsdf.conformance.files import write_request

            write_request(args.write_request, reference, views=views, n_samples=args.samples,
                          float32=args.float32)
            print(f"wrote {args.write_request}: answer it, then run with --candidate "
                  f"ANSWERS --request {args.write_request}")
            return 0
        candidate = candidate_from_text(args.candidate, args.request)
    except (ValueError, TypeError, OSError) as exc:
        return fail(str(exc))
    report = compare(reference, candidate, views=views, n_samples=args.samples,
                     float32=args.float32, same_sampling=not args.other_sampling)
    print(report)
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "report.md").write_text(report.markdown(), encoding="utf-8")
        (out / "report.json").write_text(report.to_json(), encoding="utf-8")
        print(f"wrote {out / 'report.md'} and {out / 'report.json'}")
    return 0 if report.passed else 1


def _views(view_args):
    """``--view COS PHI`` pairs as directions, or None (``ValueError`` for a cosine outside
    [-1, 0) or (0, 1])."""
    import numpy as np

    if not view_args:
        return None
    c = np.array([v[0] for v in view_args])
    if np.any(np.abs(c) > 1.0) or np.any(c == 0.0):
        raise ValueError(f"--view cosines {c.tolist()}: allowed in [-1, 0) or (0, 1]")
    s = np.sqrt(1.0 - c * c)
    phi = np.array([v[1] for v in view_args])
    return np.stack([s * np.cos(phi), s * np.sin(phi), c], -1)
