"""MkDocs hook: the docstrings' cross-reference roles shown as code.

The library's docstrings name other objects as ``:func:`name```, ``:class:`~pkg.Name```
(NumPy style, for Sphinx and for readers of the source); the API reference renders them as
the name in code, its last component alone after a ``~``, as Sphinx would.
"""
from __future__ import annotations

import re

ROLE = r":(?:func|mod|class|meth|attr|data|exc|obj)?:"
# the role before a code span the Markdown already made: ":func:<code>~a.b</code>"
CODE = re.compile(ROLE + r"<code>(~?)([^<]*)</code>")
# a role still in backquotes (inside a code span: a type written in the docstring)
TICKS = re.compile(ROLE + r"`(~?)([^`]*)`")


def _name(match) -> str:
    tilde, name = match.group(1), match.group(2)
    return name.rsplit(".", 1)[-1] if tilde else name


def on_page_content(html, page, config, files):
    html = CODE.sub(lambda m: f"<code>{_name(m)}</code>", html)
    return TICKS.sub(_name, html)
