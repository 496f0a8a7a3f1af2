"""Measure ``OpenPBRSurface`` (the fast model) against ``OpenPBRSurface.reference`` (the
specification's slabs by full light transport) and write ``docs/openpbr_transport.md`` (with
``docs/figures/openpbr_transport_*.png``) and the block of ``docs/openpbr.md`` that lists
where they differ by more than ``FLAG`` in albedo.

    python -m benchmarks.openpbr_transport [--smoke] [--out DIR]

- every example material of ``materials.presets.openpbr`` the reference follows, and sweeps
  of each parameter the fast model's approximations touch: directional albedo at
  ``COS_O`` (the fast model by quadrature, the reference by Monte Carlo, with its standard
  error), the worst difference per material and per swept parameter;
- ``eval`` at fixed pairs (the reference's estimate with its error);
- reciprocity: median relative |f(wo, wi) - f(wi, wo)| of each over the same pairs (the
  reference's within its Monte-Carlo error);
- polar slices in the plane of incidence, side by side, for a few materials;
- the cost of each per evaluated pair, and of the reference's albedo at one view.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from adobe_bsdf.materials import OpenPBRSurface, presets
from benchmarks import DOCS, generated_by, pyplot, report_main, with_block

METHOD_PAGE = "openpbr.md"
COS_O = (1.0, 0.7, 0.4, 0.15)
#: the albedo difference beyond which ``docs/openpbr.md`` names the case
FLAG = 0.02
#: the swept parameters: {name: (base parameters, swept input, values)}
SWEEPS = {
    "coat_weight": ({"base_color": 0.6, "coat_roughness": 0.1}, "coat_weight",
                    (0.0, 0.5, 1.0)),
    "coat_color": ({"base_color": 0.8, "coat_weight": 1.0, "coat_roughness": 0.1},
                   "coat_color", ((0.9, 0.7, 0.5), (0.5, 0.5, 0.8), (0.2, 0.2, 0.2))),
    "coat_roughness": ({"base_color": 0.6, "coat_weight": 1.0}, "coat_roughness",
                       (0.0, 0.3, 0.7)),
    "coat_ior": ({"base_color": 0.6, "coat_weight": 1.0, "coat_roughness": 0.2}, "coat_ior",
                 (1.2, 1.6, 2.5)),
    "coat_darkening": ({"base_color": (0.8, 0.4, 0.2), "coat_weight": 1.0,
                        "coat_roughness": 0.2}, "coat_darkening", (0.0, 0.5, 1.0)),
    "fuzz_weight": ({"base_color": 0.4, "fuzz_roughness": 0.5}, "fuzz_weight",
                    (0.5, 1.0)),
    "fuzz_roughness": ({"base_color": 0.4, "fuzz_weight": 1.0}, "fuzz_roughness",
                       (0.1, 0.5, 1.0)),
    "fuzz_color": ({"base_color": 0.4, "fuzz_weight": 1.0}, "fuzz_color",
                   ((0.9, 0.6, 0.3), (0.3, 0.3, 0.3))),
    "metalness under a coat": ({"base_color": (0.9, 0.6, 0.3), "coat_weight": 1.0,
                                "coat_roughness": 0.1, "specular_roughness": 0.3},
                               "base_metalness", (0.0, 0.5, 1.0)),
    "transmission_weight": ({"specular_roughness": 0.3}, "transmission_weight",
                            (0.5, 1.0)),
    "subsurface_weight": ({"subsurface_color": (0.9, 0.6, 0.4)}, "subsurface_weight",
                          (0.5, 1.0)),
    "geometry_thin_walled": ({"base_color": 0.7, "subsurface_weight": 0.5,
                              "transmission_weight": 0.3, "coat_weight": 0.5,
                              "coat_roughness": 0.2, "specular_roughness": 0.3},
                             "geometry_thin_walled", (True,)),
}
#: emitting materials whose emission the page compares: {name: parameters}
EMITTERS = {
    "under a clear coat, light base": {"emission_luminance": 100.0, "base_color": 0.8,
                                       "coat_weight": 1.0, "coat_roughness": 0.2},
    "under a tinted coat, dark base": {"emission_luminance": 100.0, "base_color": 0.1,
                                       "coat_weight": 1.0, "coat_roughness": 0.3,
                                       "coat_color": (0.8, 0.5, 0.3)},
    "under the fuzz": {"emission_luminance": 100.0, "base_color": 0.5, "fuzz_weight": 1.0},
}
#: materials whose polar slices the page shows
SLICES = ("coated blue", "fuzz grey", "half metal, coat, fuzz")


def _direction(mu, phi=0.0):
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


def _pairs(n, seed=5):
    rng = np.random.default_rng(seed)
    mu = rng.uniform(0.2, 1.0, (2, n))
    return (_direction(mu[0], rng.uniform(0, 2 * np.pi, n)),
            _direction(mu[1], rng.uniform(0, 2 * np.pi, n)))


def _refused(params):
    """Why the reference refuses a material (None if it follows it)."""
    try:
        OpenPBRSurface(**params).reference()
    except ValueError as error:
        return str(error).split(":")[0]
    return None


def _compare(params, n_mc, n_eval, pairs):
    """Albedo by angle of both, eval at pairs, reciprocity, costs (``params``: the inputs,
    or a built ``OpenPBRSurface``)."""
    fast = params if isinstance(params, OpenPBRSurface) else OpenPBRSurface(**params)
    start = time.perf_counter()
    ref = fast.reference(n_samples=n_eval)
    build = time.perf_counter() - start
    wo = _direction(np.array(COS_O), 0.7)
    E_fast = fast.albedo(wo)
    start = time.perf_counter()
    E_ref, se = ref.albedo(wo, method="mc", n_samples=n_mc, return_error=True)
    t_albedo = (time.perf_counter() - start) / len(COS_O)
    a, b = pairs
    start = time.perf_counter()
    f_ref, e_ref = ref.eval_with_error(a, b)
    t_ref = (time.perf_counter() - start) / len(a)
    g_ref, h_ref = ref.eval_with_error(b, a)
    start = time.perf_counter()
    f_fast = fast.eval(a, b)
    t_fast = (time.perf_counter() - start) / len(a)
    g_fast = fast.eval(b, a)

    def asymmetry(f, g):
        scale = np.maximum(np.maximum(np.abs(f), np.abs(g)), 1e-6)
        return float(np.median(np.abs(f - g) / scale))

    within = float(np.mean(np.abs(f_ref - g_ref) <= 3.0 * np.hypot(e_ref, h_ref) + 1e-12))
    return dict(E_fast=E_fast, E_ref=E_ref, se=se, f_fast=f_fast, f_ref=f_ref, e_ref=e_ref,
                worst=float(np.max(np.abs(E_fast - E_ref))),
                recip_fast=asymmetry(f_fast, g_fast), recip_ref=asymmetry(f_ref, g_ref),
                recip_within=within, t_fast=t_fast, t_ref=t_ref, t_albedo=t_albedo,
                build=build)


def _slice_figure(plt, path, rows):
    """f cos theta_i in the plane of incidence, cos theta_o = 0.7, both side by side."""
    fig, axes = plt.subplots(1, len(rows), figsize=(4.2 * len(rows), 3.4), squeeze=False)
    for ax, (name, theta, fast, ref, err) in zip(axes[0], rows, strict=True):
        for ch, color in enumerate(("tab:red", "tab:green", "tab:blue")):
            ax.plot(np.degrees(theta), fast[:, ch], color=color, lw=1.5,
                    label="fast" if ch == 0 else None)
            ax.errorbar(np.degrees(theta), ref[:, ch], yerr=err[:, ch], color=color, fmt="o",
                        ms=2.5, lw=0.8, label="structure" if ch == 0 else None)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("θ_i in the plane of incidence (°)")
        ax.set_ylabel("f cos θ_i")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _slices(names, n_eval, n_theta):
    rows = []
    theta = np.linspace(-85.0, 85.0, n_theta) * np.pi / 180.0
    wo = _direction(np.array(0.7), np.pi)
    wi = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], -1)
    for name in names:
        fast = OpenPBRSurface(**presets.openpbr[name])
        ref = fast.reference(n_samples=n_eval)
        f, e = ref.eval_with_error(np.broadcast_to(wo, wi.shape), wi)
        cos = np.cos(theta)[:, None]
        rows.append((name, theta, fast.eval(wo, wi) * cos, f * cos, e * cos))
    return rows


def compute(smoke: bool):
    n_mc, n_eval, n_pairs = (2_000, 8, 4) if smoke else (40_000, 128, 12)
    pairs = _pairs(n_pairs)
    examples, refused = {}, {}
    names = list(presets.openpbr)[:3] if smoke else list(presets.openpbr)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in names:
            why = _refused(presets.openpbr[name])
            if why:
                refused[name] = why
            else:
                examples[name] = _compare(presets.openpbr[name], n_mc, n_eval, pairs)
        sweeps = {}
        for label, (base, key, values) in (list(SWEEPS.items())[:1] if smoke
                                           else SWEEPS.items()):
            sweeps[label] = [(v, _compare({**base, key: v}, n_mc, n_eval, pairs))
                             for v in (values[:1] if smoke else values)]
        slices = _slices(SLICES[:1] if smoke else SLICES, n_eval, 5 if smoke else 25)
        documents = {}
        for name, material in ({} if smoke else mtlx_examples()).items():
            try:
                documents[name] = _compare(material, n_mc // 4, n_eval // 4, pairs)
            except ValueError as error:
                refused[name] = str(error).split(":")[0]
        proposed = {} if smoke else proposals(sweeps)
        emitted = {name: _emission(params, 256 if smoke else 4096)
                   for name, params in (list(EMITTERS.items())[:1] if smoke
                                        else EMITTERS.items())}
    return (examples, refused, sweeps, slices,
            dict(n_mc=n_mc, n_eval=n_eval, n_pairs=n_pairs, proposed=proposed,
                 emitted=emitted, documents=documents))


def mtlx_examples() -> dict:
    """{file stem: OpenPBRSurface} of the OpenPBR example documents (MaterialX) in a folder
    named ``openpbr_examples`` beside the checkout, as ``tests/test_mtlx.py`` finds them;
    empty where there is none."""
    from adobe_bsdf.io import load_mtlx

    root = Path(__file__).resolve().parents[1]
    files = sorted(f for folder in root.parent.glob("*/openpbr_examples")
                   for f in folder.glob("*.mtlx"))
    out = {}
    for f in files:
        for i, (name, material) in enumerate(load_mtlx(f).items()):
            out[f.stem if i == 0 else f"{f.stem}/{name}"] = material
    return out


def _emission(params, n):
    """(fast, structure, its standard error) of the emitted radiance at ``COS_O``, RGB."""
    wo = _direction(np.array(COS_O), 0.7)
    fast = OpenPBRSurface(**params)
    L, se = fast.reference().emission_with_error(wo, n_samples=n)
    return fast.emission(wo), L, se


def _tinted_fuzz_reflection_only(params):
    """The fuzz proposal: the base under the white fuzz's 1 - E_fuzz(wo) (the coloured
    flakes absorb what they do not reflect) instead of 1 - fuzz_color E_fuzz(wo): the fast
    model's albedo less F (1 - fuzz_color) E_fuzz(wo) E_under(wo)."""
    wo = _direction(np.array(COS_O), 0.7)
    fast = OpenPBRSurface(**params)
    under = OpenPBRSurface(**{**params, "fuzz_weight": 0.0}).albedo(wo)
    E_fuzz = fast.lobes["fuzz"].albedo(wo)
    c = np.broadcast_to(np.asarray(params["fuzz_color"], dtype=float), (3,))
    return fast.albedo(wo) - params["fuzz_weight"] * (1.0 - c) * E_fuzz * under


def _observed_subsurface(params):
    """The subsurface proposal: the fast model's subsurface albedo set to what the mapped
    medium shows under the interface, A (1 - rbar) / (1 - A rbar), A the half-space albedo
    of the medium (``media.half_space_albedo``) and rbar the interface's reflectance of
    cosine-distributed light from inside (the structure's ``transport.diffuse_albedo``)."""
    from adobe_bsdf import media
    from adobe_bsdf.materials.openpbr import transport

    wo = _direction(np.array(COS_O), 0.7)
    fast = OpenPBRSurface(**params)
    ref = fast.reference()
    slab = next(p for p in ref.parts if getattr(p, "_height", 0.0) == transport.HALF_SPACE_DEPTH)
    rbar = 2.0 - 1.0 / transport.diffuse_albedo(slab.top, 0.5)
    m = fast.media()["subsurface"][1]
    A = media.half_space_albedo(m.sigma_s / m.sigma_t, g=float(m.g)).value
    observed = A * (1.0 - rbar) / (1.0 - A * rbar)
    return OpenPBRSurface(**{**params, "subsurface_color": observed}).albedo(wo)


#: measured proposals: {name: (what it changes, swept parameter of ``SWEEPS``, albedo)}
PROPOSALS = {
    "fuzz: tint its reflection only": (
        "the base under 1 − F E_fuzz(ω_o) (the white fuzz's) instead of 1 − F fuzz_color "
        "E_fuzz(ω_o): coloured flakes absorb what they do not reflect", "fuzz_color",
        _tinted_fuzz_reflection_only),
    "subsurface: the colour it shows": (
        "the EON albedo A (1 − r̄) / (1 − A r̄) of the mapped medium under the interface "
        "(A its half-space albedo, r̄ the interface's internal reflectance of diffuse light) "
        "instead of subsurface_color", "subsurface_weight", _observed_subsurface),
}


def proposals(sweeps):
    """{name: [(value, fast's worst |dE|, the proposal's, its standard error)]} against the
    structure's albedo of the sweep ``PROPOSALS`` names."""
    out = {}
    for name, (_, label, albedo) in PROPOSALS.items():
        base, key, _ = SWEEPS[label]
        rows = []
        for v, r in sweeps.get(label, []):
            E = albedo({**base, key: v})
            rows.append((v, r["worst"], float(np.max(np.abs(E - r["E_ref"]))),
                         float(r["se"].max())))
        out[name] = rows
    return out


def _rgb(x):
    return "(" + ", ".join(f"{v:.4f}" for v in np.asarray(x)) + ")"


def _albedo_rows(label, r):
    out = []
    for k, mu in enumerate(COS_O):
        d = np.abs(r["E_fast"][k] - r["E_ref"][k]).max()
        out.append(f"| {label} | {mu:g} | {_rgb(r['E_fast'][k])} | {_rgb(r['E_ref'][k])} ± "
                   f"{r['se'][k].max():.4f} | {d:.4f} |")
    return out


def _flagged(examples, sweeps, documents=None):
    """[(case, worst difference)] beyond ``FLAG`` (beyond 3 sigma too)."""
    out = []
    cases = [(n, r) for n, r in examples.items()]
    cases += [(f"the example document {n}", r) for n, r in (documents or {}).items()]
    cases += [(f"{label} = {v}", r) for label, rows in sweeps.items() for v, r in rows]
    for name, r in cases:
        d = np.abs(r["E_fast"] - r["E_ref"])
        if np.any((d > FLAG) & (d > 3.0 * r["se"])):
            out.append((name, float(d.max())))
    return out


def markdown(examples, refused, sweeps, slices, sizes, seconds):
    out = [generated_by("benchmarks.openpbr_transport", seconds, METHOD_PAGE), "",
           "# OpenPBR: the fast model against the structure itself", "",
           "`OpenPBRSurface` approximates the light transport through the specification's "
           "slabs (albedo scaling, coat darkening and roughening, the LTC fuzz); "
           "`OpenPBRSurface.reference()` follows it by random walks ([openpbr.md]"
           "(openpbr.md), \"The structure itself\"). Albedo E(ω_o) at cos θ_o ∈ "
           f"{{{', '.join(f'{m:g}' for m in COS_O)}}} (azimuth 0.7): the fast model by "
           f"quadrature, the structure by {sizes['n_mc']} walks (± one standard error). "
           f"`eval` and reciprocity at {sizes['n_pairs']} random pairs (cosines in [0.2, 1]), "
           f"the structure's eval from {sizes['n_eval']} walks per pair.", ""]
    out += ["## Example materials", "",
            "| material | cos θ_o | E fast | E structure | \\|Δ\\| |", "|---|---|---|---|---|"]
    for name, r in examples.items():
        out += _albedo_rows(name, r)
    if refused:
        out += ["", "Not followed yet by the structure (refused, with the input named): "
                + "; ".join(f"{n} ({why})" for n, why in refused.items()) + "."]
    if sizes.get("documents"):
        out += ["", "## The OpenPBR example documents", "",
                f"The {len(sizes['documents'])} MaterialX examples of the OpenPBR repository "
                "(v1.1.1, read by `io.load_mtlx` from a folder named `openpbr_examples` beside "
                f"the checkout), the structure from {sizes['n_mc'] // 4} walks per view: the "
                "worst |ΔE| over the angles.", "",
                "| document | worst \\|ΔE\\| | ± | at cos θ_o |", "|---|---|---|---|"]
        for name, r in sizes["documents"].items():
            d = np.abs(r["E_fast"] - r["E_ref"]).max(-1)
            k = int(np.argmax(d))
            out.append(f"| {name} | {d[k]:.4f} | {r['se'][k].max():.4f} | {COS_O[k]:g} |")
    out += ["", "## Sweeps of the parameters the approximations touch", "",
            "| parameter | value | worst \\|ΔE\\| over the angles | at cos θ_o |",
            "|---|---|---|---|"]
    for label, rows in sweeps.items():
        for v, r in rows:
            d = np.abs(r["E_fast"] - r["E_ref"]).max(-1)
            k = int(np.argmax(d))
            out.append(f"| {label} | {v} | {d[k]:.4f} (± {r['se'][k].max():.4f}) | "
                       f"{COS_O[k]:g} |")
    out += ["", "Worst per parameter: " + "; ".join(
        f"{label} {max(r['worst'] for _, r in rows):.4f}" for label, rows in sweeps.items())
        + ".", ""]
    out += ["## eval at pairs and reciprocity", "",
            "Median over the pairs of |f_fast − f_structure| / f_structure (luminance-free: "
            "the largest channel), and each one's median relative asymmetry "
            "|f(ω_o, ω_i) − f(ω_i, ω_o)| / max; for the structure, the share of pairs whose "
            "asymmetry is within 3 standard errors (it is reciprocal: what remains is its "
            "Monte-Carlo error).", "",
            "| material | median relative eval difference | fast asymmetry | structure "
            "asymmetry | structure within 3σ |", "|---|---|---|---|---|"]
    for name, r in examples.items():
        rel = np.abs(r["f_fast"] - r["f_ref"]).max(-1) / np.maximum(r["f_ref"].max(-1), 1e-6)
        out.append(f"| {name} | {np.median(rel):.3f} | {r['recip_fast']:.2e} | "
                   f"{r['recip_ref']:.2e} | {r['recip_within']:.0%} |")
    out += ["", "## Polar slices", "",
            "f cos θ_i in the plane of incidence at cos θ_o = 0.7: lines the fast model, "
            "points the structure (bars: one standard error).", "",
            "![slices](figures/openpbr_transport_slices.png)", ""]
    if sizes.get("emitted"):
        out += ["## Emission", "",
                "Radiance emitted towards ω_o (W m⁻² sr⁻¹, RGB): the fast model's one pass "
                "through the layers (`emission`) against the structure's walks "
                "(`reference().emission_with_error`, light sent back down and reflected up "
                "by the base included), and the largest relative difference.", "",
                "| emitter | cos θ_o | fast | structure | relative \\|Δ\\| |",
                "|---|---|---|---|---|"]
        for name, (fast, L, se) in sizes["emitted"].items():
            for k, mu in enumerate(COS_O):
                rel = np.abs(fast[k] - L[k]).max() / L[k].max()
                out.append(f"| {name} | {mu:g} | {_rgb(fast[k])} | {_rgb(L[k])} ± "
                           f"{se[k].max():.4f} | {rel:.3f} |")
        out.append("")
    if sizes.get("proposed"):
        out += ["## Proposals, measured", "",
                "Cheap changes to the fast model where it is furthest from the structure, "
                "each measured against the same walks as the sweep it answers: the worst "
                "|ΔE| over the angles of the fast model as it is and of the proposal.", "",
                "| proposal | what it changes | value | fast | proposal | ± |",
                "|---|---|---|---|---|---|"]
        for name, rows in sizes["proposed"].items():
            for v, fast, prop, se in rows:
                out.append(f"| {name} | {PROPOSALS[name][0]} | {v} | {fast:.4f} | "
                           f"{prop:.4f} | {se:.4f} |")
        out.append("")
    out += ["## Cost", "",
            "Per evaluated pair (one batch of the pairs above), and the structure's albedo "
            f"at one view from {sizes['n_mc']} walks (its standard error beside it); one run, "
            "one thread.", "",
            "| material | fast eval (µs / pair) | structure eval (ms / pair) | ratio | "
            "structure albedo at one view (s) | its standard error |", "|---|---|---|---|---|---|"]
    for name, r in examples.items():
        out.append(f"| {name} | {1e6 * r['t_fast']:.1f} | {1e3 * r['t_ref']:.1f} | "
                   f"{r['t_ref'] / r['t_fast']:.0f}× | {r['t_albedo']:.1f} | "
                   f"{r['se'].max():.4f} |")
    return "\n".join(out) + "\n"


def _flag_block(examples, sweeps, proposed=None, documents=None):
    flagged = _flagged(examples, sweeps, documents)
    if not flagged:
        return (f"No case of [openpbr_transport.md](openpbr_transport.md) differs from the "
                f"structure by more than {FLAG} in albedo.")
    text = (f"Where the fast model is further than {FLAG} in albedo from the structure "
            "(beyond 3 standard errors; measured on [openpbr_transport.md]"
            "(openpbr_transport.md)): " + "; ".join(f"{n} ({d:.3f})" for n, d in flagged)
            + ".")
    for name, rows in (proposed or {}).items():
        text += (f"\n\nProposed, {name}: {PROPOSALS[name][0]}. Worst |ΔE| against the "
                 "structure, the fast model → the proposal: " + "; ".join(
                     f"{PROPOSALS[name][1]} = {v}: {fast:.3f} → {prop:.3f}"
                     for v, fast, prop, _ in rows) + ".")
    return text


def run(out: Path | None, smoke: bool) -> Path:
    docs = DOCS if out is None else Path(out)
    docs.mkdir(parents=True, exist_ok=True)
    (docs / "figures").mkdir(exist_ok=True)
    start = time.perf_counter()
    examples, refused, sweeps, slices, sizes = compute(smoke)
    _slice_figure(pyplot(), docs / "figures" / "openpbr_transport_slices.png", slices)
    path = docs / "openpbr_transport.md"
    path.write_text(markdown(examples, refused, sweeps, slices, sizes,
                             time.perf_counter() - start), encoding="utf-8")
    page = docs / "openpbr.md"
    if out is None:
        page.write_text(with_block(page.read_text(encoding="utf-8"), "openpbr_transport",
                                   _flag_block(examples, sweeps, sizes.get("proposed"),
                                               sizes.get("documents"))),
                       encoding="utf-8")
    return path


def main(argv=None) -> int:
    return report_main(run, "OpenPBR: the fast model against the structure itself", argv)


if __name__ == "__main__":
    raise SystemExit(main())
