"""MkDocs hook: the command line's reference written from its own parser.

A page's line ``<!-- cli-help -->`` becomes the ``--help`` text of ``symcable`` and of each
of its commands, so the reference cannot drift from the code.
"""
from __future__ import annotations

import argparse

MARKER = "<!-- cli-help -->"


def _help_text() -> str:
    from symcable.cli.main import build_parser
    parser = build_parser()
    parts = ["### symcable", "", "```text", parser.format_help().rstrip(), "```", ""]
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, sub in subs.choices.items():
        parts += [f"### symcable {name}", "", "```text", sub.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


def on_page_markdown(markdown, page, config, files):
    if MARKER in markdown:
        markdown = markdown.replace(MARKER, _help_text())
    return markdown
