"""Figures of lobes, albedos, Fresnel curves and chi-square tests (matplotlib).

Small helpers for notebooks and the documentation's figures. Each takes an optional ``ax``
(a new figure is made when it is None) and returns the Axes it drew on (the Figure for
multi-panel plots). Every curve and image is evaluated in one vectorised call of the lobe.
matplotlib is imported when a function draws, so ``import adobe_bsdf`` does not need it.

Public API
----------
``polar_slice(lobe, wo_or_theta_o, ax, quantity, channel, n, log)``
    the lobe in the plane of incidence, theta_i from -pi to pi (transmission included)
``hemisphere_image(lobe, wo, quantity, size, projection, lower, ax, channel)``
    image over the upper or lower hemisphere of wi, equal-area or orthographic, colourbar
``hemisphere_directions(xy, projection, lower)``
    the image plane -> direction map that ``hemisphere_image`` draws with
``chi2_histograms(result, axes)``
    observed and expected histograms of a ``validation.Chi2Result``, with the p-value
``albedo_curves(lobes, method, n, ax, channel)``
    directional albedo E(mu) against mu = cos theta_o for several lobes
``furnace_curves(lobes, method, n, ax, channel, difference)``
    the same against the white-furnace value 1 (E - 1 or E)
``fresnel_curves(models, n, ax, channel)``
    reflectance of Fresnel models against cos theta
``metal_fresnel(name, ax, n, illuminant)``
    a measured metal: exact spectral Fresnel vs Schlick, F82-tint and Hoffman's F82
``sphere_grid(scene, size, spp, seed, exposure, scale)``
    rendered spheres side by side: a ``paper_figures.Scene`` or a dict of label -> lobe

Colour: ``channel`` selects what is drawn of an RGB value: None (the three channels R, G, B,
drawn red, green and blue), ``"luminance"`` (Rec. 709, ``adobe_bsdf.bsdf.luminance``) or a
channel index 0, 1, 2. Scalar quantities (the pdf, a grey Fresnel model) are one curve.

References
----------
[ShirleyChiu1997] the concentric disk map (``sampling.concentric_disk``); the disk ->
hemisphere map ``z = 1 - r^2`` is equal-area.
[Kutz2021, §2, Table 1, Fig. 4] metals: exact Fresnel, Schlick, F82, F82-tint.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from adobe_bsdf import _params, fresnel, render, spectral
from adobe_bsdf.bsdf import Lobe, luminance
from adobe_bsdf.sampling import concentric_disk

__all__ = ["QUANTITIES", "PROJECTIONS", "polar_slice", "hemisphere_image",
           "hemisphere_directions", "chi2_histograms", "albedo_curves", "furnace_curves",
           "fresnel_curves", "metal_fresnel", "sphere_grid"]

#: what a lobe plot shows: f, the sampling density, or f |cos theta_i|
QUANTITIES = ("eval", "pdf", "eval_cos")
#: image plane of ``hemisphere_image``: equal-area (Shirley-Chiu square) or orthographic disk
PROJECTIONS = ("concentric", "orthographic")
#: bottom of the logarithmic radial axis of ``polar_slice``, relative to its largest value
LOG_RANGE = 1e-6
#: values of ``channel``
CHANNELS = (None, "luminance", 0, 1, 2)
_LABELS = {"eval": r"$f(\omega_o, \omega_i)$", "pdf": r"pdf$(\omega_o, \omega_i)$",
           "eval_cos": r"$f(\omega_o, \omega_i)\,|\cos\theta_i|$"}
_RGB = (("R", "tab:red"), ("G", "tab:green"), ("B", "tab:blue"))
_STYLES = ("-", "--", ":", "-.")


# -- shared helpers ---------------------------------------------------------------------------
def _pyplot():
    """``matplotlib.pyplot``, imported on first use."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("adobe_bsdf.plot needs matplotlib: pip install -e '.[test]'") from exc
    return plt


def _axes(ax, polar: bool = False):
    """``ax``, or the Axes of a new figure (polar if asked)."""
    if ax is None:
        return _pyplot().subplots(subplot_kw={"projection": "polar"} if polar else None)[1]
    if polar and ax.name != "polar":
        raise ValueError(f"ax has projection {ax.name!r}; allowed: a 'polar' Axes")
    return ax


def _values(lobe: Lobe, wo, wi, quantity: str) -> np.ndarray:
    """``quantity`` of ``lobe`` at the pairs (wo, wi): RGB ``(..., 3)``, or ``(...)`` for
    the pdf."""
    _params.choice("quantity", quantity, QUANTITIES)
    if quantity == "pdf":
        return lobe.pdf(wo, wi)
    f = lobe.eval(wo, wi)
    return f * np.abs(wi[..., 2:]) if quantity == "eval_cos" else f


#: one curve to draw: label suffix, colour (None: the Axes' cycle), values
_Curve = tuple[str, str | None, np.ndarray]


def _channel_curves(values: np.ndarray, channel, ndim: int) -> list[_Curve]:
    """``(suffix, colour, values)`` of the curves to draw of ``values`` with ``ndim`` batch
    axes: three RGB channels, the luminance or one channel (``CHANNELS``); one curve when
    the values are scalar."""
    _params.choice("channel", channel, CHANNELS)
    if values.ndim == ndim:
        return [("", None, values)]
    if channel is None:
        return [(f" {name}", colour, values[..., i]) for i, (name, colour) in enumerate(_RGB)]
    if channel == "luminance":
        return [("", None, luminance(values))]
    return [(f" {_RGB[channel][0]}", _RGB[channel][1], values[..., channel])]


def _scalar_image(values: np.ndarray, channel) -> np.ndarray:
    """One value per pixel (``channel`` not None) of scalar ``(m,)`` or RGB ``(m, 3)``
    values."""
    if channel is None:
        raise ValueError(f"channel = {channel!r}: an image needs one of {CHANNELS[1:]}")
    return _channel_curves(values, channel, 1)[0][2]


def _draw_curves(ax, x, curves: Mapping[str, np.ndarray], channel, **legend):
    """Plot the ``(n,)`` or ``(n, 3)`` values of each label against ``x`` and add a legend
    (``legend``: its keyword arguments) if any curve has a label; channels keep their colour
    and the labels take turns of line style."""
    for i, (label, values) in enumerate(curves.items()):
        style = _STYLES[i % len(_STYLES)]
        for suffix, colour, y in _channel_curves(np.asarray(values), channel, 1):
            ax.plot(x, y, label=f"{label}{suffix}".strip(), color=colour,
                    linestyle=style if colour else "-")
    if any(ax.get_legend_handles_labels()[1]):
        ax.legend(fontsize="small", **legend)
    return ax


def _one_direction(wo) -> np.ndarray:
    """``wo`` checked to be one unit direction ``(3,)``."""
    wo = _params.direction("wo", wo)
    if wo.shape != (3,):
        raise ValueError(f"wo has shape {wo.shape}; allowed: one direction (3,)")
    return wo


def _mu_grid(n: int) -> np.ndarray:
    """``n`` cosines in (0, 1], ending at normal incidence (grazing mu = 0 left out)."""
    n = _params.integer("n", n, 2)
    return np.linspace(0.0, 1.0, n + 1)[1:]


def _wo_of_mu(mu: np.ndarray) -> np.ndarray:
    """Outgoing directions ``(..., 3)`` of cosines ``mu`` in the x-z plane (x >= 0)."""
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], axis=-1)


# -- lobes ------------------------------------------------------------------------------------
def polar_slice(lobe: Lobe, wo_or_theta_o, ax=None, quantity: str = "eval", channel=None,
                n: int = 721, log: bool = False):
    """The lobe in the plane of incidence, on a polar axis.

    Parameters
    ----------
    lobe : Lobe
        A lobe with scalar parameters.
    wo_or_theta_o : float or array_like (3,)
        The outgoing direction, or its polar angle theta_o in [0, pi] (radians; azimuth 0).
    ax : matplotlib polar Axes, optional
    quantity : {"eval", "pdf", "eval_cos"}
        f(wo, wi), the sampling density, or f |cos theta_i|.
    channel : None, "luminance", 0, 1 or 2
        RGB as three lines (default), their luminance, or one channel.
    n : int
        Directions, in [2, inf), evenly spaced in theta_i over [-pi, pi].
    log : bool
        Logarithmic radial axis (``LOG_RANGE`` to 1.5 times the largest value), unless the
        values are all 0.

    Returns
    -------
    matplotlib Axes

    Notes
    -----
    wi(theta_i) = (-sin theta_i cos phi_o, -sin theta_i sin phi_o, cos theta_i): the signed
    angle theta_i > 0 is on the mirror side (phi_i = phi_o + pi), theta_i < 0 on the side of
    wo (phi_i = phi_o); |theta_i| > pi/2 is below the horizon (the refracted peak of a
    dielectric lies at theta_i = pi - theta_t). The line's x data is theta_i, its y data the
    value. Zero is up, the mirror side to the right; a dashed grey line marks wo.
    """
    _params.choice("quantity", quantity, QUANTITIES)
    wo = (_one_direction(wo_or_theta_o) if np.ndim(wo_or_theta_o) else
          _wo_of_mu(np.cos(_params.real("wo_or_theta_o", wo_or_theta_o, 0.0, np.pi))))
    theta = np.linspace(-np.pi, np.pi, _params.integer("n", n, 2))
    phi_o = np.arctan2(wo[1], wo[0])
    wi = np.stack([-np.sin(theta) * np.cos(phi_o), -np.sin(theta) * np.sin(phi_o),
                   np.cos(theta)], axis=-1)
    values = _values(lobe, wo, wi, quantity)
    ax = _axes(ax, polar=True)
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    _draw_curves(ax, theta, {"": values}, channel, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.set_title(_LABELS[quantity] + (", luminance" if channel == "luminance" else ""), pad=16)
    ax.axvline(-np.arccos(np.clip(wo[2], -1.0, 1.0)), color="0.5", linestyle="--",
               linewidth=0.8, label="_wo")
    top = float(np.max(values))
    if log and top > 0.0:  # (a slice of zeros, e.g. of a delta lobe, stays linear)
        ax.set_rlim(top * LOG_RANGE, top * 1.5)
        ax.set_rscale("log")
    return ax


def hemisphere_directions(xy, projection: str = "concentric", lower: bool = False):
    """Directions of points ``xy`` ``(..., 2)`` of the image plane [-1, 1]^2.

    Parameters
    ----------
    xy : array_like (..., 2)
        Image-plane points (x right, y up), in [-1, 1].
    projection : {"concentric", "orthographic"}
        ``"concentric"``: Shirley and Chiu's square -> disk map followed by the equal-area
        disk -> hemisphere map (r, phi) -> (r sqrt(2 - r^2) (cos phi, sin phi), 1 - r^2);
        the whole square covers the hemisphere and equal areas of the square cover equal
        solid angles (a pixel of a ``size``-square image: 2 pi / size^2).
        ``"orthographic"``: the hemisphere seen from far along the normal,
        (x, y, sqrt(1 - x^2 - y^2)); points outside the unit disk have no direction.
    lower : bool
        Mirror the directions below the surface (z < 0), as seen through it from above.

    Returns
    -------
    wi : ndarray (..., 3)
        Unit directions; ``+z`` (or ``-z``) where ``valid`` is False.
    valid : ndarray (...) of bool
    """
    _params.choice("projection", projection, PROJECTIONS)
    xy = _params.real("xy", xy, -1.0, 1.0)
    if xy.ndim == 0 or xy.shape[-1] != 2:
        raise ValueError(f"xy has shape {xy.shape}; allowed: points (..., 2)")
    if projection == "concentric":
        d = concentric_disk(0.5 * (xy + 1.0))
        r2 = np.minimum(np.sum(d * d, axis=-1), 1.0)
        wi = np.concatenate([d * np.sqrt(2.0 - r2)[..., None], (1.0 - r2)[..., None]], axis=-1)
        valid = np.ones(r2.shape, dtype=bool)
    else:
        r2 = np.sum(xy * xy, axis=-1)
        valid = r2 <= 1.0
        z = np.sqrt(np.maximum(1.0 - r2, 0.0))
        wi = np.where(valid[..., None], np.concatenate([xy, z[..., None]], axis=-1),
                      np.array([0.0, 0.0, 1.0]))
    return wi * np.array([1.0, 1.0, -1.0 if lower else 1.0]), valid


def hemisphere_image(lobe: Lobe, wo, quantity: str = "eval", size: int = 128,
                     projection: str = "concentric", lower: bool = False, ax=None,
                     channel="luminance"):
    """Image of the lobe over the hemisphere of wi, with a colourbar.

    Parameters
    ----------
    lobe : Lobe
        A lobe with scalar parameters.
    wo : array_like (3,)
        Outgoing direction.
    quantity : {"eval", "pdf", "eval_cos"}
    size : int
        Pixels per side, in [1, inf); pixel centres at ``(2 i + 1) / size - 1``.
    projection : {"concentric", "orthographic"}
        Equal-area or orthographic image plane (``hemisphere_directions``).
    lower : bool
        The hemisphere below the surface (transmission for ``wo`` above).
    ax : matplotlib Axes, optional
    channel : "luminance", 0, 1 or 2
        What of an RGB value each pixel shows.

    Returns
    -------
    matplotlib Axes
        Its image (``ax.images[0]``, ``origin="lower"``, extent [-1, 1]^2) holds the values,
        masked outside the disk of the orthographic projection.
    """
    size = _params.integer("size", size, 1)
    wo = _one_direction(wo)
    centres = (2.0 * np.arange(size) + 1.0) / size - 1.0
    xy = np.stack(np.meshgrid(centres, centres), axis=-1)  # [row = y, column = x]
    wi, valid = hemisphere_directions(xy, projection, lower)
    image = _scalar_image(_values(lobe, wo, wi[valid], quantity), channel)
    pixels = np.ma.masked_all((size, size))
    pixels[valid] = image
    ax = _axes(ax)
    shown = ax.imshow(pixels, origin="lower", extent=(-1.0, 1.0, -1.0, 1.0), cmap="magma",
                      interpolation="nearest")
    ax.figure.colorbar(shown, ax=ax, label=_LABELS[quantity])
    ax.set_title(f"{'lower' if lower else 'upper'} hemisphere, {projection}")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_xticks([])
    ax.set_yticks([])
    return ax


# -- validation -------------------------------------------------------------------------------
def chi2_histograms(result, axes=None):
    """Observed and expected histograms of a chi-square test side by side.

    Parameters
    ----------
    result : adobe_bsdf.validation.Chi2Result
    axes : pair of matplotlib Axes, optional

    Returns
    -------
    matplotlib Figure
        Two panels, observed then expected counts per cell over (phi, theta) in degrees
        (the grid's own edges, so warped rings show their true widths), on one colour scale
        with one colourbar; the figure's title gives the p-value and the verdict.
    """
    axes = _pyplot().subplots(1, 2, figsize=(10, 4), sharey=True)[1] if axes is None else axes
    phi, theta = np.degrees(result.phi_edges), np.degrees(result.theta_edges)
    top = max(float(np.max(result.observed)), float(np.max(result.expected)), 1.0)
    for ax, name in zip(axes, ("observed", "expected"), strict=True):
        mesh = ax.pcolormesh(phi, theta, getattr(result, name), vmin=0.0, vmax=top,
                             cmap="viridis")
        ax.set_title(name)
        ax.set_xlabel(r"$\phi$ (deg)")
    axes[0].set_ylabel(r"$\theta$ from the grid's pole (deg)")
    figure = axes[0].figure
    figure.colorbar(mesh, ax=list(axes), label="samples per cell")
    verdict = "pass" if result.passed else "FAIL"
    figure.suptitle(f"chi-square {verdict}: p = {result.p_value:.3g} "
                    f"(threshold {result.significance:.3g}), dof = {result.dof}")
    return figure


# -- energy -----------------------------------------------------------------------------------
def albedo_curves(lobes: Mapping[str, Lobe], method: str = "table", n: int = 64, ax=None,
                  channel="luminance"):
    """Directional albedo E(mu) against mu = cos theta_o for several lobes.

    Parameters
    ----------
    lobes : dict of label -> Lobe
        Lobes with scalar parameters.
    method : {"table", "quadrature", "mc"}
        Passed to ``Lobe.albedo``.
    n : int
        Cosines, in [2, inf), evenly spaced over (0, 1] (grazing mu = 0 left out).
    ax : matplotlib Axes, optional
    channel : None, "luminance", 0, 1 or 2

    Returns
    -------
    matplotlib Axes
    """
    return _energy_plot(lobes, method, n, ax, channel, offset=0.0, ylabel=r"$E(\mu)$")


def furnace_curves(lobes: Mapping[str, Lobe], method: str = "table", n: int = 64, ax=None,
                   channel="luminance", difference: bool = True):
    """White-furnace view of ``albedo_curves``: E(mu) - 1 (``difference``) or E(mu) with the
    line E = 1, for lobes that should conserve energy. Parameters as ``albedo_curves``.

    Returns
    -------
    matplotlib Axes
    """
    ax = _energy_plot(lobes, method, n, ax, channel, offset=1.0 if difference else 0.0,
                      ylabel=r"$E(\mu) - 1$" if difference else r"$E(\mu)$")
    ax.axhline(0.0 if difference else 1.0, color="0.3", linewidth=0.8, label="_furnace")
    return ax


def _energy_plot(lobes, method, n, ax, channel, offset: float, ylabel: str):
    """E(mu) - ``offset`` of each lobe against mu."""
    mu = _mu_grid(n)
    wo = _wo_of_mu(mu)
    ax = _draw_curves(_axes(ax), mu, {label: lobe.albedo(wo, method=method) - offset
                                      for label, lobe in lobes.items()}, channel)
    ax.set_xlabel(r"$\mu = \cos\theta_o$")
    ax.set_ylabel(ylabel)
    ax.set_title(f"directional albedo ({method})")
    return ax


# -- Fresnel ----------------------------------------------------------------------------------
def fresnel_curves(models: Mapping[str, Callable[[np.ndarray], np.ndarray]], n: int = 256,
                   ax=None, channel=None):
    """Reflectance of Fresnel models against mu = cos theta.

    Parameters
    ----------
    models : dict of label -> callable
        ``model(mu)`` with ``mu`` ``(n,)`` returns RGB ``(n, 3)`` (or grey ``(n,)``), e.g.
        ``fresnel.F82Tint(f0, tint)`` or ``lambda mu: fresnel.schlick(mu, 0.04)``.
    n : int
        Cosines, in [2, inf), evenly spaced over [0, 1].
    ax : matplotlib Axes, optional
    channel : None, "luminance", 0, 1 or 2

    Returns
    -------
    matplotlib Axes
    """
    mu = np.linspace(0.0, 1.0, _params.integer("n", n, 2))
    ax = _draw_curves(_axes(ax), mu, {label: model(mu) for label, model in models.items()},
                      channel)
    ax.set_xlabel(r"$\mu = \cos\theta$")
    ax.set_ylabel("reflectance")
    return ax


def metal_fresnel(name: str, ax=None, n: int = 256, illuminant: str = "D65"):
    """A measured metal's Fresnel reflectance and its approximations, per RGB channel.

    Four models of the metal ``name`` (one of ``spectral.METALS``, the shipped spectra of
    the metals of [Kutz2021, Table 1] and a few more): the exact conductor Fresnel of the measured
    n + i k, wavelength by wavelength, turned into linear Rec. 709 by
    ``spectral.reflectance_to_rgb`` (not clipped); Schlick with F0; F82-tint with F0 and the
    tint; Hoffman's original F82 through the exact value at cos theta = 1/7 (clipped to
    [0, 1]). F0 and the tint are ``spectral.fit_f82_tint`` of the same spectrum, which may
    differ from the published ``materials.presets.metals`` (other measurements).

    Parameters
    ----------
    name : str
    ax : matplotlib Axes, optional
    n : int
        Cosines, in [2, inf).
    illuminant : str
        colour-science illuminant of the colour conversion.

    Returns
    -------
    matplotlib Axes
    """
    wavelengths, eta, k = spectral.metal_ior(name)
    fit = spectral.fit_f82_tint(wavelengths, eta, k, illuminant)

    def exact(mu):
        spectrum = fresnel.conductor(np.asarray(mu)[..., None], eta[:, None], k[:, None])
        return spectral.reflectance_to_rgb(wavelengths, spectrum[..., 0], illuminant)

    h = np.clip(exact(np.array(fresnel.COS_THETA_MAX)), 0.0, 1.0)
    ax = fresnel_curves({"exact (spectral)": exact,
                         "Schlick": lambda mu: fresnel.schlick(mu, fit.f0),
                         "F82-tint": lambda mu: fresnel.f82_tint(mu, fit.f0, fit.tint),
                         "F82 (Hoffman)": lambda mu: fresnel.f82(mu, fit.f0, h)}, n=n, ax=ax)
    ax.set_title(f"{name}: F0 = {np.array2string(fit.f0, precision=3)}, "
                 f"tint = {np.array2string(fit.tint, precision=3)}")
    return ax


# -- rendered spheres -------------------------------------------------------------------------
def sphere_grid(scene, size: int = 96, spp: int = 32, seed: int = 0, exposure: float = 1.0,
                scale: float = 1.75, env: str = "sky", ncols: int | None = None):
    """Spheres rendered by ``render.sphere`` side by side, one labelled panel each.

    Parameters
    ----------
    scene : paper_figures.Scene or dict of label -> Lobe
        A scene brings its own environment, columns, title and zoom (``env`` and ``ncols``
        are then ignored; ``size`` and ``scale`` are multiplied by the zoom).
    size, spp, seed : passed to ``render.sphere`` (every sphere with the same seed).
    exposure : float   radiance multiplier before ``render.to_srgb8``.
    scale : float      inches per panel.
    env : str          environment for a dict of lobes.
    ncols : int        panels per row for a dict of lobes (default: all in one row).

    Returns
    -------
    matplotlib Figure
    """
    materials, title = scene, None
    if hasattr(scene, "materials"):
        materials, env, ncols = scene.materials, scene.env, scene.ncols
        title = f"{scene.source}:\n{scene.title}" if ncols < 4 else f"{scene.source}: {scene.title}"
        size, scale = max(1, round(size * scene.zoom)), scale * scene.zoom
    labels = list(materials)
    ncols = ncols or len(labels)
    nrows = -(-len(labels) // ncols)
    fig, axes = _pyplot().subplots(nrows, ncols, figsize=(scale * ncols, (scale + 0.15) * nrows),
                                   squeeze=False)
    for ax in axes.flat:
        ax.set_axis_off()
    for ax, label in zip(axes.flat, labels, strict=False):
        image = render.sphere(materials[label], env=env, size=size, spp=spp, seed=seed,
                              progress=False)
        ax.imshow(render.to_srgb8(exposure * image))
        ax.set_title(label, fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
