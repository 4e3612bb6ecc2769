"""The documentation site builds strictly with the example gallery executed
(``mkdocs build --strict``, ``pip install ".[docs]"``): every script of ``examples/`` runs, and
a broken link, a missing page or a docstring the API reference cannot read fails the build.
(Apart from tests/test_docs.py so that the two run on different workers.)
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))


def test_site_builds_strictly(tmp_path):
    """``mkdocs build --strict``: the gallery's scripts executed, every link resolved."""
    env = dict(os.environ, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q",
                        "-d", str(tmp_path / "site")], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=1800)
    assert r.returncode == 0, r.stderr[-6000:]
    gallery = tmp_path / "site" / "generated" / "gallery"
    pages = [p for p in gallery.glob("plot_*/index.html")]
    assert len(pages) == len(EXAMPLES), sorted(p.parent.name for p in pages)
    images = list((tmp_path / "site").rglob("*plot_*.png"))
    assert len(images) >= len(EXAMPLES), "an example's figure is missing from the site"
