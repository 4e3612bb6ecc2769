"""Run the code blocks of a Markdown page, as a reader would paste them.

Every fenced block of a page runs, by its language:

- ``python``: all of a page's Python blocks in order, in one namespace (a page builds on its
  earlier blocks), in a fresh process whose working folder is a new temporary folder
  (``MPLBACKEND=Agg``);
- ``bash`` / ``sh``: each block by ``bash -e`` in that same folder, in its place among the
  Python blocks (they run in one session, which starts each bash block), with ``.venv`` in the folder linked to the running Python's
  environment (so ``.venv/bin/symcable`` and ``symcable`` both work); lines that create an
  environment or install into one (``python3 -m venv``, ``pip install``) are left out: CI
  runs exactly those itself (``.ci/run``);
- ``toml``: parsed; a block with a ``model`` key or a ``lines`` table is a whole scene and is
  loaded by :func:`symcable.load_scene` (it must validate);
- ``text`` (and a block with no language): output or prose, not run.

Any other language is refused, so that no block escapes by its label.

Run as ``python tests/docs_blocks.py PAGE.md [...]`` to check pages by hand.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

RUN = {"python", "bash", "sh", "toml"}
SKIP = {"text", ""}
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>```+|~~~+)\s*(?P<lang>[\w+-]*)[^\n]*$")
SETUP = re.compile(r"python3? -m venv|pip install")


def blocks(text: str) -> list[tuple[str, str, int]]:
    """``(language, code, line)`` of every fenced block of ``text`` (code dedented)."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, lang, start = m["fence"], m["lang"].lower(), i + 1
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i])
            i += 1
        out.append((lang, textwrap.dedent("\n".join(body)) + "\n", start))
        i += 1
    return out


_PRELUDE = """
import subprocess, sys, traceback
_ns = {"__name__": "__main__"}
def _block(code, page, line):
    try:
        exec(compile(code, f"{page}:{line}", "exec"), _ns)
    except SystemExit:
        raise
    except BaseException:
        traceback.print_exc()
        print(f"FAILED: the python block at {page}:{line}", file=sys.stderr)
        sys.exit(1)
def _bash(code, page, line):
    r = subprocess.run(["bash", "-e", "-c", code], capture_output=True, text=True)
    if r.returncode:
        print(r.stdout[-2000:], r.stderr[-3000:], file=sys.stderr)
        print(f"FAILED: the bash block at {page}:{line} (exit {r.returncode})", file=sys.stderr)
        sys.exit(1)
"""


def page_script(path: str | os.PathLike) -> tuple[str, list[str]]:
    """The page's python and bash blocks as one script (a reader's session), and the
    failures found without running anything (unknown labels, TOML that does not parse)."""
    path = Path(path)
    page = path.name
    failures, parts = [], [_PRELUDE]
    for lang, code, line in blocks(path.read_text(encoding="utf-8")):
        if lang == "python":
            parts.append(f"_block({code!r}, {page!r}, {line})")
        elif lang in ("bash", "sh"):
            kept = "\n".join(ln for ln in code.splitlines() if not SETUP.search(ln))
            parts.append(f"_bash({kept!r}, {page!r}, {line})")
        elif lang == "toml":
            failures += _toml_parse(code, page, line)
        elif lang not in SKIP:
            failures.append(f"{page}:{line}: a ```{lang} block: label it python, bash, toml "
                            "or text")
    return "\n".join(parts), failures


def run_page(path: str | os.PathLike, timeout: float = 900.0) -> list[str]:
    """Run every block of the page at ``path`` (module docstring); returns a list of
    failures (empty when every block ran), each naming the block's line."""
    script, failures = page_script(path)
    with tempfile.TemporaryDirectory() as tmp:
        os.symlink(sys.prefix, os.path.join(tmp, ".venv"))
        env = dict(os.environ, MPLBACKEND="Agg",
                   PATH=os.path.join(sys.prefix, "bin") + os.pathsep + os.environ.get("PATH", ""))
        for lang, code, line in blocks(Path(path).read_text(encoding="utf-8")):
            if lang == "toml" and not _toml_parse(code, Path(path).name, line):
                failures += _toml_scene(code, Path(path).name, line, env, tmp)
        r = subprocess.run([sys.executable, "-c", script], cwd=tmp, env=env,
                           capture_output=True, text=True, timeout=timeout)
        if r.returncode:
            failures.append(f"{Path(path).name}: {r.stderr[-4000:]}")
    return failures


def _toml_parse(code: str, page: str, line: int) -> list[str]:
    try:
        tomllib.loads(code)
    except tomllib.TOMLDecodeError as exc:
        return [f"{page}:{line}: toml block does not parse: {exc}"]
    return []


def _toml_scene(code: str, page: str, line: int, env: dict, tmp: str) -> list[str]:
    data = tomllib.loads(code)
    if "model" not in data and "lines" not in data:
        return []
    probe = ("import sys, symcable as sc\n"
             "try:\n    import tomllib\nexcept ModuleNotFoundError:\n    import tomli as tomllib\n"
             "sc.load_scene(tomllib.loads(sys.stdin.read()))\n")
    r = subprocess.run([sys.executable, "-c", probe], input=code, cwd=tmp, env=env,
                       capture_output=True, text=True, timeout=120)
    if r.returncode:
        return [f"{page}:{line}: toml scene does not load:\n{r.stderr[-2000:]}"]
    return []


if __name__ == "__main__":
    bad = []
    for p in sys.argv[1:]:
        got = run_page(p)
        print(f"{p}: {'ok' if not got else f'{len(got)} failure(s)'}")
        bad += got
    print("\n".join(bad))
    sys.exit(1 if bad else 0)
