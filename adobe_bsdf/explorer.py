"""Explore a lobe or a material in Jupyter: controls generated from its parameter specification
and four live panels.

Public API
----------
``explore(target, **fixed)``   an ``Explorer`` of ``target`` (a name of
                               ``explorables.EXPLORABLES``, a material class or a lobe class),
                               shown in the notebook
``Explorer``                   its controls, panels and the data behind them

Each parameter of the target's ``ParameterSpec`` that ``fixed`` does not set gets a control:
a slider over its soft range (so no value outside the hard range can be entered; without a
soft range and with no upper bound, up to ten times the default or 1), a colour
picker for a colour (its 8-bit value / 255; the default exactly until it is moved), a
checkbox for a switch, a dropdown for a choice, two angle sliders for a unit vector; a
parameter the material derives gets an "auto" box beside its control. A slider sets the
view angle theta_o. The panels, drawn by ``plot`` and ``render``:

- the polar slice f |cos theta_i| in the plane of incidence at theta_o (``plot.polar_slice``);
- the hemisphere image of f |cos theta_i| at theta_o (``plot.hemisphere_image``);
- the directional albedo over theta_o by the tables (``plot.albedo_curves``), with the
  quadrature value at theta_o and its difference from the table;
- a small sphere under the sky (``render.sphere``, few samples per pixel).

The first three follow every change after ``DEBOUNCE`` seconds; the sphere and the
quadrature wait until the controls have rested ``REST`` seconds (the last sphere stays
until then). With ``reference=True`` a material that has a structure followed by full light
transport (``OpenPBRSurface.reference``) shows it too, at rest: points with error bars on the
polar slice and its Monte-Carlo albedo at theta_o, the worst difference in the title line.
The title line shows the lobes the current parameters make active (the rest are never
built) and the time of one
``eval`` per pair. Without a widget front end (``ipywidgets`` missing, or outside a Jupyter
kernel) ``explore`` says so and draws the panels once, for the given values. The figure is
shown as a PNG in an image widget (its state is kept in the notebook), so no matplotlib
widget backend is needed.
"""

from __future__ import annotations

import functools
import time

import numpy as np

from adobe_bsdf import plot, render
from adobe_bsdf.explorables import explorable

__all__ = ["explore", "Explorer", "DEBOUNCE", "REST", "SIZES"]

#: seconds after a change before the fast panels are redrawn (a newer change restarts it)
DEBOUNCE = 0.15
#: seconds of rest before the sphere is rendered and the quadrature albedo computed
REST = 0.8
#: panel sizes: (hemisphere pixels, polar-slice directions, albedo cosines, sphere pixels,
#: sphere samples per pixel)
SIZES = {"normal": (64, 361, 32, 96, 16), "small": (16, 91, 8, 16, 2)}
#: the structure's panels at rest: (slice points, walks per point, albedo samples)
REFERENCE_SIZES = {"normal": (19, 256, 40_000), "small": (5, 16, 2_000)}
#: pairs timed for the eval cost shown
_TIMED = 4096
#: room for the longest parameter names beside their controls
_STYLE = {"description_width": "12em"}


def _hex(rgb) -> str:
    return "#" + "".join(f"{int(round(255 * float(c))):02x}" for c in np.broadcast_to(rgb, 3))


def _rgb(text: str) -> tuple:
    return tuple(int(text[i:i + 2], 16) / 255.0 for i in (1, 3, 5))


def _angles(v) -> tuple:
    """(theta, phi) in degrees of a vector."""
    v = np.asarray(v, dtype=np.float64)
    v = v / np.linalg.norm(v)
    return (float(np.degrees(np.arccos(np.clip(v[2], -1.0, 1.0)))),
            float(np.degrees(np.arctan2(v[1], v[0])) % 360.0))


def _vector(theta, phi) -> tuple:
    t, p = np.radians(theta), np.radians(phi)
    return (float(np.sin(t) * np.cos(p)), float(np.sin(t) * np.sin(p)), float(np.cos(t)))


class _StaticWidget:
    """A stand-in for an ipywidgets widget where ipywidgets is missing: it holds its value
    and options and draws nothing."""

    def __init__(self, *children, **options):
        self.children, self.disabled = children, False
        self.__dict__.update(options)

    def observe(self, callback, names=None):
        pass


class _StaticWidgets:
    """The widget classes ``Explorer`` uses, as ``_StaticWidget``."""

    def __getattr__(self, name):
        return _StaticWidget


def _widgets():
    try:
        import ipywidgets
    except ImportError:
        return _StaticWidgets()
    return ipywidgets


class _Control:
    """The widget of one parameter and the parameter value it stands for."""

    def __init__(self, widgets, parameter):
        self.parameter = p = parameter
        kind, label = p.kind, p.name
        self.auto = (widgets.Checkbox(value=True, description="auto", indent=False)
                     if p.default is None else None)
        if kind == "real":
            lo, hi = p.soft or p.hard
            if not np.isfinite(hi):  # no soft range: up to ten times the default (or 1)
                hi = lo + 10.0 * max(abs(p.default or 0.0), 1.0)
            step = (hi - lo) / 200.0
            lo = lo + step if p.lo_open and lo == p.hard[0] else lo
            hi = hi - step if p.hi_open and hi == p.hard[1] else hi
            value = lo if p.default is None else float(np.clip(p.default, lo, hi))
            self.widget = widgets.FloatSlider(value=value, min=lo, max=hi, step=step,
                                              description=label, readout_format=".3g",
                                              continuous_update=True, style=_STYLE)
            self.parts = [self.widget]
        elif kind == "color":
            default = (0.5, 0.5, 0.5) if p.default is None else p.default
            self._exact = (_hex(default), tuple(np.broadcast_to(default, 3).tolist()))
            self.widget = widgets.ColorPicker(value=self._exact[0], description=label,
                                              concise=False, style=_STYLE)
            self.parts = [self.widget]
        elif kind == "bool":
            self.widget = widgets.Checkbox(value=bool(p.default), description=label,
                                           style=_STYLE)
            self.parts = [self.widget]
        elif kind == "choice":
            self.widget = widgets.Dropdown(options=list(p.choices), value=p.default,
                                           description=label, style=_STYLE)
            self.parts = [self.widget]
        else:  # a unit vector: polar and azimuthal angle
            theta, phi = _angles(p.default)
            self.parts = [widgets.FloatSlider(value=theta, min=0.0, max=180.0, step=0.5,
                                              description=f"{label} θ", style=_STYLE),
                          widgets.FloatSlider(value=phi, min=0.0, max=359.5, step=0.5,
                                              description="φ")]
            self.widget = widgets.HBox(self.parts)
        if self.auto is not None:
            for part in self.parts:
                part.disabled = True
            self.auto.observe(self._toggle, names="value")
            self.box = widgets.HBox([self.widget, self.auto])
        else:
            self.box = self.widget

    def _toggle(self, change):
        for part in self.parts:
            part.disabled = change["new"]

    @property
    def value(self):
        """The parameter's value (None: derived by the material)."""
        if self.auto is not None and self.auto.value:
            return None
        p = self.parameter
        if p.kind == "color":
            text = self.widget.value
            return self._exact[1] if text == self._exact[0] else _rgb(text)
        if p.kind == "vector":
            return _vector(self.parts[0].value, self.parts[1].value)
        return self.widget.value

    def observe(self, callback):
        for part in self.parts + ([self.auto] if self.auto is not None else []):
            part.observe(callback, names="value")


class Explorer:
    """Controls and panels of one target (see the module docstring).

    Parameters
    ----------
    target : str, material class or lobe class
    fixed : dict
        Parameters held at these values (no control).
    size : {"normal", "small"}
        Panel resolutions (``SIZES``); "small" for tests and quick looks.
    theta_o : float
        Initial view angle in degrees, [0, 89].

    Attributes
    ----------
    controls : dict of name -> widget container
    view : the view-angle slider
    data : dict
        What the panels show, recomputed by ``update``: "theta_i", "slice" (f |cos| along the
        slice), "hemisphere" (the image's values), "mu", "albedo" (table, RGB), "albedo_at"
        (table at theta_o), and after a slow update "quadrature", "quadrature_error",
        "table_error" (|table - quadrature|), "sphere"; "active" (names of the active
        lobes), "eval_ns" (time of one eval per pair).
    figure : matplotlib Figure of the four panels
    live : bool
        Whether a change of a control redraws (False: set several, then call ``update``).
    """

    def __init__(self, target, fixed: dict | None = None, size: str = "normal",
                 theta_o: float = 45.0, reference: bool = False):
        widgets = _widgets()
        #: whether the panels show the structure itself at rest (``Explorer`` docstring)
        self.reference = bool(reference)
        self.target = explorable(target)
        spec = self.target.parameters
        self.fixed = dict(fixed or {})
        unknown = set(self.fixed) - set(spec.parameters)
        if unknown:
            raise ValueError(f"fixed parameter(s) {sorted(unknown)}: not parameters of "
                             f"{self.target.name}; allowed {list(spec.parameters)}")
        for name, value in self.fixed.items():
            if value is not None:
                spec[name].validate(value)
        if size not in SIZES:
            raise ValueError(f"size = {size!r}: allowed one of {tuple(SIZES)}")
        self.size = size
        self._controls = {p.name: _Control(widgets, p) for p in spec
                          if p.name not in self.fixed}
        self.controls = {name: c.box for name, c in self._controls.items()}
        self.view = widgets.FloatSlider(value=float(theta_o), min=0.0, max=89.0, step=0.5,
                                        description="θo (°)", style=_STYLE)
        self.status = widgets.HTML()
        self.image = widgets.Image(format="png")
        self.interactive = _front_end()
        self.data: dict = {}
        self.figure = None
        self._pending: list = []
        self._built = (None, None)
        self._sphere = None
        #: whether a change of a control redraws (False: set several, then ``update()``)
        self.live = True
        for control in self._controls.values():
            control.observe(self._changed)
        self.view.observe(self._changed, names="value")
        self.widget = widgets.VBox([
            widgets.HTML(f"<b>{self.target.name}</b> — {self.target.doc}"),
            widgets.HBox([widgets.VBox([self.view, *self.controls.values()]),
                          widgets.VBox([self.status, self.image])])])

    # -- the material ---------------------------------------------------------------------
    def values(self) -> dict:
        """The parameters as the controls and ``fixed`` set them (derived ones left out)."""
        values = {name: c.value for name, c in self._controls.items()}
        values.update(self.fixed)
        return {name: v for name, v in values.items() if v is not None}

    def lobe(self):
        """The target built from ``values()`` (rebuilt only when they change)."""
        values = self.values()
        key = repr(sorted(values.items()))
        if self._built[0] != key:
            validated = self.target.parameters.validate(values)
            self._built = (key, self.target.build(**validated))
        return self._built[1]

    # -- updates --------------------------------------------------------------------------
    def _changed(self, change=None):
        """Redraw after ``DEBOUNCE`` s without a newer change, refine after ``REST`` s; at
        once where no event loop runs (a script, a test)."""
        for handle in self._pending:
            handle.cancel()
        self._pending = []
        if not self.live:
            return
        try:
            import asyncio
            loop = asyncio.get_running_loop()
        except RuntimeError:
            self.update()
            return
        self._pending = [loop.call_later(DEBOUNCE, self.update),
                         loop.call_later(REST, self.update, True)]

    def update(self, slow: bool = False) -> dict:
        """Recompute the panels (with ``slow``, the sphere at rest and the quadrature too),
        redraw the figure and return ``data``."""
        lobe = self.lobe()
        pixels, n_slice, n_mu, sphere_px, spp = SIZES[self.size]
        theta_o = np.radians(self.view.value)
        wo = np.array([np.sin(theta_o), 0.0, np.cos(theta_o)])
        data = {"active": list(getattr(lobe, "lobes", {type(lobe).__name__: lobe})),
                "eval_ns": self._eval_ns(lobe, wo)}
        import matplotlib.pyplot as plt

        if self.figure is None:  # a fixed layout: tight_layout would double the time
            self.figure = plt.figure(figsize=(11, 8))
            self.figure.subplots_adjust(left=0.05, right=0.9, bottom=0.07, top=0.93,
                                        wspace=0.45, hspace=0.35)
            plt.close(self.figure)  # shown through the image widget, not by pyplot
        fig = self.figure
        fig.clf()
        ax_slice = fig.add_subplot(2, 2, 1, projection="polar")
        plot.polar_slice(lobe, theta_o, ax=ax_slice, quantity="eval_cos", n=n_slice)
        rgb = ax_slice.lines[:3]  # then the line of wo
        data["theta_i"] = np.asarray(rgb[0].get_xdata())
        data["slice"] = np.stack([np.asarray(line.get_ydata()) for line in rgb], -1)
        ax_hemi = fig.add_subplot(2, 2, 2)
        plot.hemisphere_image(lobe, wo, quantity="eval_cos", size=pixels, ax=ax_hemi)
        data["hemisphere"] = np.ma.getdata(ax_hemi.images[0].get_array()).copy()
        ax_albedo = fig.add_subplot(2, 2, 3)
        data.update(self._albedo(lobe, wo, ax_albedo, n_mu, slow))
        if slow and self.reference:
            data.update(self._structure(lobe, wo, ax_slice, ax_albedo))
        ax_sphere = fig.add_subplot(2, 2, 4)
        if slow:
            self._sphere = render.sphere(lobe, env="sky", size=sphere_px, spp=spp, seed=0,
                                         progress=False)
        if self._sphere is not None:
            data["sphere"] = self._sphere
            ax_sphere.imshow(render.tone_map(self._sphere, exposure=-1.0, tonemap="aces"))
        ax_sphere.set_title(f"sphere under the sky, {spp} spp" if slow else
                            "sphere (rendered when the controls rest)")
        ax_sphere.set_axis_off()
        self.data = data
        self.status.value = (f"active lobes: {', '.join(data['active'])} — eval "
                             f"{data['eval_ns']:.0f} ns per pair" + self._accuracy(data))
        self._show()
        return data

    def _albedo(self, lobe, wo, ax, n_mu, slow) -> dict:
        out = {}
        try:
            plot.albedo_curves({"table": lobe}, method="table", n=n_mu, ax=ax, channel=None)
        except ValueError as exc:  # no table for this lobe: the quadrature alone
            ax.set_title(f"no table: {exc}"[:80])
            out["table_unavailable"] = str(exc)
        else:
            out["mu"] = np.asarray(ax.lines[0].get_xdata())
            out["albedo"] = np.stack([np.asarray(line.get_ydata()) for line in ax.lines[:3]], -1)
            out["albedo_at"] = lobe.albedo(wo, method="table")
        if slow:
            value, error = lobe.albedo(wo, method="quadrature", return_error=True)
            out["quadrature"], out["quadrature_error"] = value, error
            if "albedo_at" in out:
                out["table_error"] = np.abs(out["albedo_at"] - value)
            ax.plot([wo[2]] * 3, value, "k+", markersize=10, label="quadrature")
        ax.axvline(wo[2], color="0.5", linestyle="--", linewidth=0.8)
        return out

    def _structure(self, lobe, wo, ax_slice, ax_albedo) -> dict:
        """The structure followed by full light transport (``lobe.reference()``), where the
        material has one: its f |cos theta_i| at points of the polar slice with one standard
        error, and its albedo at theta_o; "reference_slice", "reference_slice_error",
        "reference_theta_i", "reference_albedo", "reference_albedo_error"."""
        make = getattr(lobe, "reference", None)
        if make is None:
            return {"reference_unavailable": f"{type(lobe).__name__} has no structure"}
        n_points, n_walks, n_albedo = REFERENCE_SIZES[self.size]
        try:
            structure = make(n_samples=n_walks)
        except ValueError as exc:  # an input the structure does not follow yet
            return {"reference_unavailable": str(exc)}
        theta = np.linspace(-85.0, 85.0, n_points) * np.pi / 180.0
        # ``plot.polar_slice``'s angle: theta_i > 0 on the mirror side (wo has azimuth 0)
        wi = np.stack([-np.sin(theta), np.zeros_like(theta), np.cos(theta)], -1)
        f, e = structure.eval_with_error(np.broadcast_to(wo, wi.shape), wi)
        cos = np.abs(np.cos(theta))[:, None]
        E, sigma = structure.albedo(wo, method="mc", n_samples=n_albedo, return_error=True)
        ax_slice.errorbar(theta, (f * cos).max(-1), yerr=(e * cos).max(-1), fmt="k.",
                          ms=3, lw=0.6, label="structure")
        ax_albedo.errorbar([wo[2]] * 3, E, yerr=sigma, fmt="kx", ms=6, label="structure")
        return {"reference_theta_i": theta, "reference_slice": f * cos,
                "reference_slice_error": e * cos, "reference_albedo": E,
                "reference_albedo_error": sigma}

    @staticmethod
    def _eval_ns(lobe, wo) -> float:
        wi = _timed_directions()
        start = time.perf_counter()
        lobe.eval(np.broadcast_to(wo, wi.shape), wi)
        return (time.perf_counter() - start) / _TIMED * 1e9

    @staticmethod
    def _accuracy(data) -> str:
        if "table_error" not in data:
            return " — quadrature at rest"
        text = (f" — albedo at θo: table {np.max(data['albedo_at']):.5f}, quadrature "
                f"{np.max(data['quadrature']):.5f} ± {np.max(data['quadrature_error']):.1e}, "
                f"table error {np.max(data['table_error']):.1e}")
        if "reference_albedo" in data:
            text += (f"; structure {np.max(data['reference_albedo']):.4f} ± "
                     f"{np.max(data['reference_albedo_error']):.1e} (worst |Δ| "
                     f"{np.max(np.abs(data['reference_albedo'] - data['quadrature'])):.4f})")
        return text

    def _show(self):
        if not self.interactive:
            return
        import io

        png = io.BytesIO()  # a PNG, whatever the matplotlib backend
        self.figure.savefig(png, format="png")
        self.image.value = png.getvalue()


@functools.cache
def _timed_directions() -> np.ndarray:
    """The ``_TIMED`` directions on the sphere at which eval is timed (drawn once)."""
    wi = np.random.default_rng(0).normal(size=(_TIMED, 3))
    return wi / np.linalg.norm(wi, axis=-1, keepdims=True)


def _front_end() -> bool:
    """Whether widgets can be shown: ipywidgets imports and a Jupyter kernel runs."""
    try:
        import ipywidgets  # noqa: F401
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and hasattr(shell, "kernel")


def explore(target, size: str = "normal", theta_o: float = 45.0, reference: bool = False,
            **fixed):
    """Open ``target`` with controls for every parameter not in ``fixed`` (module docstring);
    ``reference=True`` adds, at rest, the structure followed by full light transport where
    the material has one (``OpenPBRSurface.reference``).

    Returns the ``Explorer`` (shown in the notebook), or, without a widget front end, the
    matplotlib Figure of the panels for the given values (with a message saying why)."""
    explorer = Explorer(target, fixed, size, theta_o, reference)
    if not explorer.interactive:
        explorer.update(slow=True)
        print("explore: no widget front end (ipywidgets in a Jupyter kernel); the panels "
              f"for {explorer.target.name} at the given values, static:")
        return explorer.figure
    from IPython.display import display

    display(explorer.widget)
    explorer.update(slow=True)
    return explorer
