"""MkDocs hook: the studies' committed figures published at their own paths.

``studies/<name>/<figure>.png`` in the repository becomes ``studies/<name>/<figure>.png`` in
the site, so the validation and performance pages show the figures the studies draw without
a copy of them in ``docs/``.
"""
from __future__ import annotations

from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]


def on_files(files, config):
    for png in sorted((ROOT / "studies").glob("*/*.png")):
        uri = png.relative_to(ROOT).as_posix()
        if files.get_file_from_path(uri) is None:
            files.append(File.generated(config, uri, abs_src_path=str(png)))
    return files
