"""Screenshot of ``notebooks/08_explore.ipynb`` as a reader sees it; writes
``docs/figures/explore.png`` (shown in the README).

    python docs/explore_screenshot.py [--out PNG] [--small]

The notebook is executed with its widget state stored (nbclient), exported to HTML
(nbconvert, "lab" template) and opened in headless Chromium (Playwright driving Debian's
``/usr/bin/chromium``, or ``--chromium PATH``); the widgets are drawn by the
``@jupyter-widgets/html-manager`` bundle, which the exported page loads from a CDN: the
script fetches it and RequireJS from the npm registry (``npm pack``) and serves them in
place of the CDN, and blocks every other outside request. Needs ``nbconvert``,
``playwright`` and ``npm``, none of them used by the library or its tests.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import tarfile
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "notebooks" / "08_explore.ipynb"
#: npm packages serving the page's scripts: the widget manager of ipywidgets 8, RequireJS
PACKAGES = ("@jupyter-widgets/html-manager@1", "requirejs@2")


def _html(small: bool) -> str:
    import nbclient
    import nbformat
    from nbconvert import HTMLExporter

    nb = nbformat.read(NOTEBOOK, as_version=4)
    env = dict(os.environ, MPLBACKEND="Agg")
    if small:
        env["ADOBE_BSDF_NOTEBOOK_SMALL"] = "1"
    old = dict(os.environ)
    os.environ.update(env)
    try:
        nbclient.NotebookClient(nb, timeout=600, kernel_name="python3", store_widget_state=True,
                                resources={"metadata": {"path": str(NOTEBOOK.parent)}}).execute()
    finally:
        os.environ.clear()
        os.environ.update(old)
    return HTMLExporter(template_name="lab").from_notebook_node(nb)[0]


def _scripts(folder: Path) -> dict:
    """``{file name: bytes}`` of the packages' files that the page asks the CDN for."""
    subprocess.run(["npm", "pack", "--silent", *PACKAGES], cwd=folder, check=True,
                   capture_output=True)
    files = {}
    for archive in folder.glob("*.tgz"):
        with tarfile.open(archive) as tar:
            for member in tar.getmembers():
                if member.isfile() and member.name.endswith(".js"):
                    files[Path(member.name).name] = tar.extractfile(member).read()
    files["require.min.js"] = files["require.js"]
    return files


def shoot(out: Path, small: bool = False, chromium: str = "/usr/bin/chromium") -> Path:
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory(prefix="adobe_bsdf_shot_") as tmp:
        tmp = Path(tmp)
        page_path = tmp / "08_explore.html"
        page_path.write_text(_html(small), encoding="utf-8")
        scripts = _scripts(tmp)

        def serve(route):
            name = route.request.url.split("?")[0].rsplit("/", 1)[-1]
            if route.request.url.startswith("file:"):
                return route.continue_()
            if name in scripts:
                return route.fulfill(body=scripts[name], content_type="application/javascript")
            return route.abort()

        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, args=[
                "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update",
                "--disable-sync"])
            page = browser.new_page(viewport={"width": 1500, "height": 1100})
            page.route("**/*", serve)
            page.goto(page_path.as_uri())
            page.wait_for_selector(".widget-slider", timeout=60_000)
            page.wait_for_timeout(1500)  # the images of the image widgets decode
            first = page.locator(".jp-OutputArea-output").filter(
                has=page.locator(".widget-slider")).first
            out.parent.mkdir(parents=True, exist_ok=True)
            first.screenshot(path=str(out))
            browser.close()
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "explore.png")
    parser.add_argument("--small", action="store_true", help="the notebook's small mode")
    parser.add_argument("--chromium", default="/usr/bin/chromium")
    args = parser.parse_args(argv)
    print(shoot(args.out, args.small, args.chromium))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
