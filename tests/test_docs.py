"""The documentation: every code block of the README and the docs pages runs (the site's
strict build is tests/test_docs_site.py).

The blocks run as a reader would paste them (:mod:`docs_blocks`), each page in a fresh
folder.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from docs_blocks import blocks, run_page

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_code_blocks_run(page):
    failures = run_page(page)
    assert not failures, "\n".join(failures)


def test_every_page_in_the_site():
    """Every page of docs/ is in the site's navigation (a page left out is unreachable)."""
    nav = (ROOT / "mkdocs.yml").read_text()
    missing = [p.name for p in PAGES[1:] if p.name not in nav]
    assert not missing, f"pages not in mkdocs.yml's nav: {missing}"


def test_readme_is_short_and_has_the_ci_commands():
    """The README is at most 150 lines and its first block holds the two commands CI runs."""
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 150
    first = blocks(text)[0][1]
    ci = (ROOT / ".ci" / "run").read_text()
    assert "symcable demo" in first and '".[test,docs]"' in first and '".[test,docs]"' in ci


def test_examples_gallery():
    """At least eight examples, each with a title and drawing a figure."""
    assert len(EXAMPLES) >= 8, [p.name for p in EXAMPLES]
    for path in EXAMPLES:
        text = path.read_text()
        assert text.lstrip().startswith('"""') and "\n# " in text.split('"""')[1], path.name
        assert "plt." in text or ".plot(" in text, f"{path.name} draws no figure"
