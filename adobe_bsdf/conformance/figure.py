"""The figure of a comparison: the reference's and the candidate's polar slices side by side
and a map of their difference over the hemisphere (matplotlib, imported when drawing)."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import plot
from adobe_bsdf.bsdf import luminance
from adobe_bsdf.conformance.compare import FLOOR
from adobe_bsdf.validation.candidate import as_lobe

__all__ = ["figure", "difference_map"]


def difference_map(reference, candidate, wo, size: int = 96, lower: bool = False):
    """``(size, size)`` relative difference of the candidate's f from the reference's
    (luminance, against |reference| + ``FLOOR`` x its largest value), over the upper (or
    ``lower``) hemisphere of wi in the equal-area projection of ``plot.hemisphere_image``."""
    wo = np.asarray(wo, dtype=np.float64)
    centres = (2.0 * np.arange(size) + 1.0) / size - 1.0
    wi, _ = plot.hemisphere_directions(np.stack(np.meshgrid(centres, centres), -1),
                                       lower=lower)
    wi = wi.reshape(-1, 3)
    wo_b = np.broadcast_to(wo, wi.shape)
    ref = luminance(reference.eval(wo_b, wi))
    cand = luminance(as_lobe(candidate).eval(wo_b, wi))
    floor = FLOOR * np.max(np.abs(ref)) + 1e-300
    return ((cand - ref) / (np.abs(ref) + floor)).reshape(size, size)


def figure(reference, candidate, wo, *, size: int = 96, lower: bool = False):
    """A matplotlib Figure: f |cos theta_i| of the reference and of the candidate in the
    plane of incidence of ``wo`` (log scale, luminance), and ``difference_map`` with a
    diverging colour scale centred on 0."""
    plt = plot._pyplot()
    fig = plt.figure(figsize=(13.5, 4.2))
    for k, (label, lobe) in enumerate((("reference", reference),
                                       ("candidate", as_lobe(candidate)))):
        ax = fig.add_subplot(1, 3, k + 1, projection="polar")
        plot.polar_slice(lobe, wo, ax, "eval_cos", "luminance", log=True)
        ax.set_title(f"{label}: f |cos θi|", pad=16)
    ax = fig.add_subplot(1, 3, 3)
    diff = difference_map(reference, candidate, wo, size, lower)
    top = float(np.nanmax(np.abs(diff))) or 1.0
    shown = ax.imshow(diff, origin="lower", extent=(-1.0, 1.0, -1.0, 1.0), cmap="RdBu_r",
                      vmin=-top, vmax=top, interpolation="nearest")
    fig.colorbar(shown, ax=ax, label="(candidate − reference) / reference")
    ax.set_title(f"difference, {'lower' if lower else 'upper'} hemisphere")
    ax.set_xticks([])
    ax.set_yticks([])
    fig.tight_layout()
    return fig
